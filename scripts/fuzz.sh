#!/usr/bin/env bash
# Fuzzes every parser with libFuzzer (ASan + UBSan): builds build/fuzz with clang
# (scripts/setup.sh fuzz), seeds each target's corpus from fuzz/seeds/<target> (and, when the real
# data is there, from ../shared/data), and runs each target for SECONDS (default 60) or RUNS
# executions, whichever comes first. Findings (crash-*, leak-*, timeout-*) land in
# build/fuzz/findings/<target>/; the script exits non-zero when a target reports one.
#
#   scripts/fuzz.sh [SECONDS] [RUNS]     e.g. scripts/fuzz.sh 600 1000000
#   FUZZ_TARGETS="carmen_log relations" scripts/fuzz.sh 30     (some targets only)
#   FUZZ_SEED=1 scripts/fuzz.sh 600 5000   (a fixed seed and run count: the same inputs each time)
#   FUZZ_MAX_LEN=4096 scripts/fuzz.sh ...  (shorter inputs: faster on the line-based logs)
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-60}"
runs="${2:--1}"
data="${VDTNAV_DATA:-../shared/data}"

all="ros_map ros_map_image vdt_map_file carmen_log relations tum_trajectory odometry_table
     point_set localizer_config pan_tilt_csv camera_calibration camera_poses point_cloud
     ros1_bag ros_messages"
read -r -a targets <<< "$(echo ${FUZZ_TARGETS:-$all})"
build=()
for t in "${targets[@]}"; do build+=("fuzz_$t"); done
scripts/setup.sh fuzz "${build[@]}"
bin=build/fuzz/fuzz
status=0
printf '%-26s %12s %10s %8s  %s\n' target executions exec/s seconds result
for t in "${targets[@]}"; do
  corpus="build/fuzz/corpus/$t"
  findings="build/fuzz/findings/$t"
  mkdir -p "$corpus" "$findings"
  cp -n fuzz/seeds/"$t"/* "$corpus"/ 2>/dev/null || true
  if [ -d "$data" ]; then  # a few real files, trimmed to what a fuzzer can mutate
    case "$t" in
      carmen_log) { zcat "$data/intel-lab/intel.gfs.log.gz" | head -c 65536 > "$corpus/intel.log"; } || true ;;
      relations) head -c 16384 "$data/intel-lab/intel.relations" > "$corpus/intel.relations" ;;
      odometry_table) head -c 16384 "$data/intel-lab/intel_910_odom_vs_corrected.txt" > "$corpus/intel.txt" ;;
      ros_map) cp "$data/ros-maps/fetch-office/4_26_15.yaml" "$corpus/fetch.yaml" ;;
      camera_poses) head -c 4096 "$data/vision/rgbd-icl/pose.txt" > "$corpus/icl_pose.txt" 2>/dev/null || true ;;
    esac
  fi
  log="build/fuzz/findings/$t.log"
  start=$(date +%s)
  set +e
  ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    "$bin/fuzz_$t" "$corpus" -max_total_time="$seconds" -runs="$runs" -timeout=10 \
    -rss_limit_mb=2048 -max_len="${FUZZ_MAX_LEN:-65536}" -print_final_stats=1 -artifact_prefix="$findings/" \
    -seed="${FUZZ_SEED:-0}" \
    > "$log" 2>&1
  rc=$?
  set -e
  execs="$(grep -m1 'stat::number_of_executed_units' "$log" | awk '{print $2}' || true)"
  secs=$(( $(date +%s) - start ))
  per="$(grep -m1 'stat::average_exec_per_sec' "$log" | awk '{print $2}' || true)"
  if [ "$rc" -eq 0 ]; then result=ok; else result="FINDING (rc $rc): $log"; status=1; fi
  printf '%-26s %12s %10s %8s  %s\n' "fuzz_$t" "${execs:-?}" "${per:-?}" "$secs" "$result"
done
exit "$status"
