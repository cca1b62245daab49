#!/usr/bin/env bash
# The main job: builds vdtnav and runs its studies on the embedded, generated default, plus the
# real-data studies when the data is there (default ../shared/data, or the path given as $1).
# Writes tables and PNG plots under out/.
set -euo pipefail
cd "$(dirname "$0")/.."
data="${1:-../shared/data}"

scripts/setup.sh release
bin=build/release/examples
mkdir -p out

echo "== [1/4] VDT maps: generated floor plan (embedded default)"
"$bin/map_demo/vdtnav_map_demo" --out out/map_demo
echo "== [2/4] Table 3.3 study: five localizers on a simulated LiDAR run (generated floor plan)"
"$bin/turtlebot_lidar/vdtnav_turtlebot_lidar" --out out/turtlebot_lidar
if [ -d "$data" ]; then
  echo "== [3/4] VDT maps: Player/Stage hospital section (real floor plan, $data)"
  "$bin/map_demo/vdtnav_map_demo" --out out/map_demo_hospital \
    --map "$data/stage_maps/hospital_section.png" --size 40x18
  echo "== [4/4] Table 3.3 study on the hospital section (the thesis's environment)"
  "$bin/turtlebot_lidar/vdtnav_turtlebot_lidar" --out out/turtlebot_lidar_hospital \
    --map "$data/stage_maps/hospital_section.png" --size 40x18
else
  echo "== no data folder at '$data': skipping the real-data studies [3/4], [4/4]"
fi
echo "== done: tables and figures in out/"
for t in out/turtlebot_lidar*/table.md; do echo "-- $t"; cat "$t"; done
