#!/usr/bin/env bash
# Times freespace-sweep on bench/sweep_3x8.yaml (3 scenarios x 8 seeds) with one worker and
# with two on a local Dask cluster; writes OUT/w1 and OUT/w2 (sweep.json holds the times) and
# prints both run times and their ratio. Usage: bench/sweep_scaling.sh BUILD_DIR OUT
set -euo pipefail
build=${1:-build}
out=${2:-out/sweep-scaling}
here=$(cd "$(dirname "$0")" && pwd)
for n in 1 2; do
  "$build/freespace-sweep" "$here/sweep_3x8.yaml" --workers "$n" --out "$out/w$n" --no-plot
done
/usr/bin/python3 - "$out" <<'PY'
import json, sys
t = {n: json.load(open(f"{sys.argv[1]}/w{n}/sweep.json"))["timing"] for n in (1, 2)}
print(f"1 worker: {t[1]['run_s']:.1f} s, 2 workers: {t[2]['run_s']:.1f} s, "
      f"ratio {t[2]['run_s'] / t[1]['run_s']:.3f} (cluster start {t[1]['startup_s']:.1f} s, "
      f"{t[2]['startup_s']:.1f} s)")
PY
