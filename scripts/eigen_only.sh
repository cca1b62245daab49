#!/usr/bin/env bash
# The layering check (issue 58, docs/architecture.md#layers-what-needs-which-dependency): vdtnav
# configured with CMake's own switches turning Ceres, OpenCV, PCL and OctoMap off configures,
# builds and installs the Eigen-only components and the CLI's 2D subcommands; its package test
# consumes vdtnav::estimation (and the rest) from that install with those packages disabled, and
# the CLI maps, localizes and evaluates a stretch of the Intel log when the data is there.
#
#   scripts/eigen_only.sh [DATA]   (default ../shared/data; run after scripts/setup.sh installed
#                                   the packages: this build only leaves some of them out)
set -euo pipefail
cd "$(dirname "$0")/.."
data="${1:-../shared/data}"
b=build/eigen-only
jobs="$(nproc)"
# The front ends (ROS bags, the cameras, the clouds) are left out too: the release build has
# built and tested them once; this build is about the layers. -O1: it proves the layering, it
# does not measure speed.
cmake -S . -B "$b" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE="-O1 -DNDEBUG" \
  -DVDTNAV_WERROR=ON -DVDTNAV_PYTHON=OFF -DVDTNAV_BUILD_FRONTENDS=OFF \
  -DCMAKE_DISABLE_FIND_PACKAGE_Ceres=ON -DCMAKE_DISABLE_FIND_PACKAGE_OpenCV=ON \
  -DCMAKE_DISABLE_FIND_PACKAGE_PCL=ON -DCMAKE_DISABLE_FIND_PACKAGE_octomap=ON | grep 'vdtnav'
cmake --build "$b" -j "$jobs"
ctest --test-dir "$b" --output-on-failure
cli="$b/tools/vdtnav/vdtnav"
# What needs a package this build left out says so, and exits as bad usage (2) or input (1).
expect_refusal() {
  local want="$1" pattern="$2"
  shift 2
  local rc=0
  "$@" > "$b/refusal.log" 2>&1 || rc=$?
  if [ "$rc" -ne "$want" ] || ! grep -q "$pattern" "$b/refusal.log"; then
    echo "expected exit $want and '$pattern' from: $*"; cat "$b/refusal.log"; exit 1
  fi
  echo "refused as expected: $* -> $(grep -m1 "$pattern" "$b/refusal.log")"
}
if [ -f "$data/intel-lab/intel.gfs.log.gz" ]; then
  w="$b/cli_intel"
  mkdir -p "$w"
  d="$data/intel-lab"
  "$cli" join-odometry --log "$d/intel.gfs.log.gz" --table "$d/intel_910_odom_vs_corrected.txt" \
    --out-raw "$w/raw.log" --out-corrected "$w/corrected.log" --out-reference "$w/corrected.tum"
  "$cli" map --log "$w/corrected.log" --resolution 0.05 --out "$w/intel_map"
  "$cli" localize --map "$w/intel_map.yaml" --log "$w/raw.log" --out "$w/traj.tum" \
    --cov "$w/cov.csv"
  "$cli" eval --traj "$w/traj.tum" --relations "$d/intel.relations" --cov "$w/cov.csv"
  expect_refusal 2 "needs OpenCV" "$cli" localize --map "$w/intel_map.yaml" --log "$w/raw.log" \
    --out "$w/p.tum" --plot "$w/p"
  expect_refusal 1 "needs Ceres" "$cli" localize --map "$w/intel_map.yaml" --log "$w/raw.log" \
    --out "$w/u.tum" --method udt-opt
  expect_refusal 1 "needs Ceres" "$cli" map --log "$w/corrected.log" --resolution 0.05 \
    --out "$w/u" --uncertain
else
  echo "no Intel log under $data: the CLI's commands are checked by their --help only"
  for c in map localize eval; do "$cli" "$c" --help > /dev/null; done
fi
echo "eigen-only: configured, built, installed and consumed without Ceres, OpenCV, PCL, OctoMap"
