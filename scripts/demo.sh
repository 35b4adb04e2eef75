#!/usr/bin/env bash
# The project's main job: installs what is missing, builds, and runs the engine on the Intel
# lab log from ../shared/data (extra arguments go to `freespace run`).
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/build.sh
data=${FREESPACE_DATA_DIR:-../shared/data}
exec ./build/freespace run --log "$data/carmen/intel-corrected.log" --config configs/indoor.yaml \
  --out out/demo --snapshot-every 150 "$@"
