#!/usr/bin/env bash
# The main job: builds vdtnav and runs its study on the embedded, generated default, plus the
# real-data studies when the data is there (default ../shared/data, or the path given as $1).
# Writes tables and PNG plots under out/.
set -euo pipefail
cd "$(dirname "$0")/.."
data="${1:-../shared/data}"

scripts/setup.sh release
bin=build/release/examples
mkdir -p out

echo "== VDT maps: generated floor plan (embedded default)"
"$bin/map_demo/vdtnav_map_demo" --out out/map_demo
if [ -d "$data" ]; then
  echo "== VDT maps: Player/Stage hospital section (real floor plan, $data)"
  "$bin/map_demo/vdtnav_map_demo" --out out/map_demo_hospital \
    --map "$data/stage_maps/hospital_section.png" --size 40x18
else
  echo "== no data folder at '$data': skipping the real-data studies"
fi
echo "== done: results in out/"
