#!/usr/bin/env bash
# The project's main job: installs what is missing, builds, and runs `freespace demo`: a
# simulated urban drive (32 s) with a ScaLa-like scanner, the estimator on every scan, scored
# against the exact truth. Writes out/demo/ (logs, truth, polygons, eval.json, demo.avi,
# snapshots); extra arguments go to `freespace demo` (e.g. --scenario highway).
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/build.sh
exec ./build/freespace demo --out out/demo "$@"
