#!/usr/bin/env bash
# The main job: builds vdtnav and runs its studies on the embedded, generated defaults, plus the
# real-data studies when the data is there (default ../shared/data, or the path given as $1).
# Writes tables and PNG plots under out/ (or the folder $VDTNAV_OUT names).
set -euo pipefail
cd "$(dirname "$0")/.."
data="${1:-../shared/data}"

# Only what it runs: the study programs, the CLI and the Python module (no tests, no benchmarks);
# the first two studies' programs first, so that a table is printed minutes after the start
# (issue 58), then the rest (vdtnav_main_job) while nothing else runs.
scripts/setup.sh release vdtnav_map_demo vdtnav_turtlebot_lidar
bin=build/release/examples
out="${VDTNAV_OUT:-out}"
mkdir -p "$out"
step_name=""
step_start=$SECONDS
# Each step says what it runs and, when the next begins, how long it took.
step() {
  if [ -n "$step_name" ]; then echo "   (${step_name%%]*}] took $((SECONDS - step_start)) s)"; fi
  step_name="$1"
  step_start=$SECONDS
  echo "== $1"
}
# Ends the current step's timing (before a build that is no step of its own).
end_step() {
  if [ -n "$step_name" ]; then echo "   (${step_name%%]*}] took $((SECONDS - step_start)) s)"; fi
  step_name=""
}
step "[1/22] VDT maps: generated floor plan (embedded default)"
"$bin/map_demo/vdtnav_map_demo" --out "$out/map_demo"
step "[2/22] Table 3.3 study: five localizers on a simulated LiDAR run (generated floor plan)"
"$bin/turtlebot_lidar/vdtnav_turtlebot_lidar" --out "$out/turtlebot_lidar"
end_step
echo "== the first table is above, ${SECONDS} s after the job began; building the other studies, the CLI and the Python module"
scripts/setup.sh release vdtnav_main_job
step "[3/22] Table 3.4 study: 6-DOF pan-tilt point-laser localization (generated 3D room)"
"$bin/pan_tilt_3d/vdtnav_pan_tilt_3d" --room --out "$out/pan_tilt_3d"
if [ -x "$bin/uav_camera/vdtnav_uav_camera" ]; then
  step "[4/22] UAV downward camera over a figure-of-eight road on a runway (generated)"
  "$bin/uav_camera/vdtnav_uav_camera" --out "$out/uav_camera"
fi
if [ -x "$bin/pmd_rgbd/vdtnav_pmd_rgbd" ]; then
  step "[5/22] PMD with a rear RGB-D camera in a generated park: ground boundaries + bearings"
  "$bin/pmd_rgbd/vdtnav_pmd_rgbd" --out "$out/pmd_rgbd"
fi
step "[6/22] Uncertain VDT maps (thesis ch. 5): Fig. 5.2, Experiments 1 and 2, localization on the fitted map (generated corridor)"
"$bin/uncertain_map/vdtnav_uncertain_map" --out "$out/uncertain_map"
step "[7/22] Active localization with one rotating range beam (thesis ch. 4, generated floor plans)"
"$bin/active_beam/vdtnav_active_beam" --out "$out/active_beam"
step "[8/22] Never lost: global localization from one scan (branch and bound vs random sampling) and the kidnapped robot (generated floor plan)"
"$bin/kidnapped/vdtnav_kidnapped" --out "$out/kidnapped"
if [ -x "$bin/lidar_3d/vdtnav_lidar_3d" ]; then
  step "[9/22] 3D LiDAR: simulated VLP-16 scans on the generated 3D room (ray cast in its own voxels) and on the room rebuilt by map3d from a noisy mapping drive, 6-DOF and 4-DOF; global localization from one scan at 40 poses"
  "$bin/lidar_3d/vdtnav_lidar_3d" --out "$out/lidar_3d"
fi
if [ -d "$data" ]; then
  step "[10/22] Active localization on the Willow Garage and fetch-office maps (real maps)"
  "$bin/active_beam/vdtnav_active_beam" --data "$data" --out "$out/active_beam_real"
  step "[11/22] VDT maps: Player/Stage hospital section (real floor plan, $data)"
  "$bin/map_demo/vdtnav_map_demo" --out "$out/map_demo_hospital" \
    --map "$data/stage_maps/hospital_section.png" --size 40x18
  step "[12/22] Table 3.3 study on the hospital section (the thesis's environment)"
  "$bin/turtlebot_lidar/vdtnav_turtlebot_lidar" --out "$out/turtlebot_lidar_hospital" \
    --map "$data/stage_maps/hospital_section.png" --size 40x18
  step "[13/22] Intel Research Lab: map from the last third, localize the first two (real log)"
  "$bin/intel_lab/vdtnav_intel_lab" --data "$data" --out "$out/intel_lab"
  if [ -f "$data/3d/dll-catec/catec.bt" ] && [ -x "$bin/pan_tilt_3d/vdtnav_pan_tilt_3d" ]; then
    step "[14/22] Table 3.4 study on the real CATEC OctoMap"
    "$bin/pan_tilt_3d/vdtnav_pan_tilt_3d" --map "$data/3d/dll-catec/catec.bt" \
      --out "$out/pan_tilt_3d_catec"
  fi
  if [ -f "$data/3d/dll-catec/catec.bt" ] && [ -x "$bin/lidar_3d/vdtnav_lidar_3d" ]; then
    step "[15/22] 3D LiDAR: simulated VLP-16 scans on the real CATEC OctoMap (ray cast in its own voxels) and on CATEC rebuilt by map3d from a noisy mapping drive; global localization from one scan at 40 poses (2-3 min)"
    "$bin/lidar_3d/vdtnav_lidar_3d" --map "$data/3d/dll-catec/catec.bt" --out "$out/lidar_3d_catec"
  fi
  if [ -f "$data/vision/aerial/aero1.jpg" ] && [ -x "$bin/uav_camera/vdtnav_uav_camera" ]; then
    step "[16/22] UAV downward camera over a real aerial photograph laid on the ground"
    "$bin/uav_camera/vdtnav_uav_camera" --texture "$data/vision/aerial/aero1.jpg" \
      --out "$out/uav_camera_photo"
  fi
  if [ -f "$data/vision/rgbd-kinect/pose.txt" ] && [ -x "$bin/pmd_rgbd/vdtnav_pmd_rgbd" ]; then
    step "[17/22] RGB-D: relative localization between recorded Kinect frames (real frames)"
    "$bin/pmd_rgbd/vdtnav_pmd_rgbd" --kinect "$data/vision/rgbd-kinect" --out "$out/pmd_rgbd_kinect"
  fi
  if [ -f "$data/intel-lab/intel.relations" ]; then
    step "[18/22] Uncertain VDT maps on the Willow Garage corridor and the Intel lab (real map and log)"
    "$bin/uncertain_map/vdtnav_uncertain_map" --data "$data" --out "$out/uncertain_map_real"
  fi
  step "[19/22] Never lost: global localization and the kidnapped robot on the hospital section, fetch-office (simulated scans) and the Intel lab (real scans and odometry); false alarms of lost detection on the real logs"
  "$bin/kidnapped/vdtnav_kidnapped" --data "$data" --out "$out/kidnapped_real"
  lpm="$data/3d/libpointmatcher"
  if [ -f "$lpm/car_cloud401.csv" ] && build/release/tools/vdtnav/vdtnav localize3d --help >/dev/null 2>&1; then
    step "[20/22] vdtnav localize3d: libpointmatcher's real car scans, each on a map of the other, from identity; the 3D LiDAR study on the pair as a sequence (scan 401 makes the map, 400 is localized)"
    mkdir -p "$out/localize3d_car"
    build/release/tools/vdtnav/vdtnav localize3d --map "$lpm/car_cloud400.csv" \
      --crop -40,-40,-12,40,40,20 --resolution 0.2 --scan "$lpm/car_cloud401.csv" --multi-start \
      --out "$out/localize3d_car/car_cloud401_in_400.yaml"
    build/release/tools/vdtnav/vdtnav localize3d --map "$lpm/car_cloud401.csv" \
      --crop -40,-40,-12,40,40,20 --resolution 0.2 --scan "$lpm/car_cloud400.csv" --multi-start \
      --out "$out/localize3d_car/car_cloud400_in_401.yaml"
    if [ -x "$bin/lidar_3d/vdtnav_lidar_3d" ] && [ -f "$lpm/carCloudList.csv" ]; then
      # The pair as a real sequence for the 3D LiDAR study (--scans DIR --poses FILE, the odd
      # scans make the map): links to the clouds in carCloudList.csv's order, named 000000.csv,
      # ..., and its 4x4 poses as KITTI 3x4 rows. The data stays where it is.
      seq="$out/lidar_3d_real_car/input"
      rm -rf "$seq"
      mkdir -p "$seq/scans"
      awk -F', *' 'NR > 1 { print $1 }' "$lpm/carCloudList.csv" | {
        k=0
        while read -r name; do
          ln -s "$(realpath "$lpm/$name")" "$seq/scans/$(printf '%06d' "$k").${name##*.}"
          k=$((k + 1))
        done
      }
      awk -F', *' 'NR > 1 { print $2, $3, $4, $5, $6, $7, $8, $9, $10, $11, $12, $13 }' \
        "$lpm/carCloudList.csv" > "$seq/poses.kitti"
      "$bin/lidar_3d/vdtnav_lidar_3d" --scans "$seq/scans" --poses "$seq/poses.kitti" \
        --out "$out/lidar_3d_real_car"
    fi
  fi
  rs="$data/3d/mulran-riverside02"
  if [ -f "$rs/odom_poses.txt" ] && [ -x "$bin/lidar_3d/vdtnav_lidar_3d" ]; then
    step "[20/22] The 3D LiDAR study on MulRan Riverside (a car's Ouster, 245 m): the odd keyframes at their SLAM poses make the map, the even ones are tracked from FAST-LIO2's odometry (~4 min)"
    "$bin/lidar_3d/vdtnav_lidar_3d" --scans "$rs/Scans" --poses "$rs/optimized_poses.txt" \
      --odom "$rs/odom_poses.txt" --global-trials 0 --out "$out/lidar_3d_riverside"
  fi
  if [ -d "$data/rosbags" ] && [ -x "$bin/ros_bags/vdtnav_ros_bags" ]; then
    step "[21/22] ROS bags: a TurtleBot 4's ROS 2 bag and a Pioneer's ROS 1 bag localized on their maps from no prior"
    "$bin/ros_bags/vdtnav_ros_bags" --data "$data" --out "$out/ros_bags"
  fi
  # The Python module (python/, -DVDTNAV_PYTHON): Debian's interpreter, the one with numpy.
  py=/usr/bin/python3
  [ -x "$py" ] || py=python3
  if compgen -G "build/release/python/vdtnav/_vdtnav*.so" >/dev/null; then
    step "[22/22] Python: the Intel study's vdt-opt run and the car pair's 3D registration through the module (examples/python)"
    if [ -f "$data/intel-lab/intel.relations" ]; then
      PYTHONPATH=build/release/python "$py" examples/python/intel_study.py --data "$data" \
        --out "$out/python_intel"
    fi
    if [ -f "$lpm/car_cloud401.csv" ] &&
       PYTHONPATH=build/release/python "$py" -c "import vdtnav; vdtnav.localize3d" 2>/dev/null; then
      PYTHONPATH=build/release/python "$py" examples/python/pair_registration_3d.py --data "$data" \
        --out "$out/python_pair3d"
    fi
  fi
else
  echo "== no data folder at '$data': skipping the real-data studies"
fi
end_step
echo "== done in ${SECONDS} s (builds included): tables and figures in $out/"
for t in "$out"/turtlebot_lidar*/table.md "$out"/intel_lab/table.md "$out"/pan_tilt_3d*/table.md \
         "$out"/lidar_3d*/table.md "$out"/uav_camera*/table.md "$out"/pmd_rgbd/table.md \
         "$out"/uncertain_map*/table.md "$out"/active_beam*/table.md "$out"/kidnapped*/table.md \
         "$out"/kidnapped_real/false_alarms.md; do
  [ -f "$t" ] || continue
  echo "-- $t"
  cat "$t"
done
if [ -f "$out"/uncertain_map_real/intel.csv ]; then
  echo "-- $out/uncertain_map_real/intel.csv"
  cat "$out"/uncertain_map_real/intel.csv
fi
if [ -f "$out"/pmd_rgbd_kinect/kinect_relative.csv ]; then
  echo "-- $out/pmd_rgbd_kinect/kinect_relative.csv"
  cat "$out"/pmd_rgbd_kinect/kinect_relative.csv
fi
for t in "$out"/lidar_3d*/global.csv "$out"/python_intel/table.csv "$out"/python_pair3d/summary.csv; do
  [ -f "$t" ] || continue
  echo "-- $t"
  cat "$t"
done
