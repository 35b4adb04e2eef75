#!/usr/bin/env bash
# `freespace bench --soak`: a short soak run (2,000 scans of urban laps, a sample every 200
# scans) writes soak.csv and soak.json in the shape docs/bench.md gives, and the process's
# memory does not grow over the run's second half. Memory only: nothing here bounds a time.
# Usage: soak_cli_test.sh FREESPACE_BINARY SOURCE_DIR OUT_DIR
set -u
bin=$1 src=$2 out=$3
rm -rf "$out" && mkdir -p "$out"
fail() { echo "FAIL: $*"; exit 1; }

"$bin" bench --soak 2000 --soak-every 200 --scenario urban --config "$src/configs/scala.yaml" \
  --backend tbb --out "$out/soak" >"$out/soak.txt" 2>"$out/soak.err" \
  || fail "bench --soak: $(cat "$out/soak.err")"
cat "$out/soak.txt"
grep -q "growth over the second half" "$out/soak.txt" || fail "no summary printed"
[ "$(grep -c "freespace bench: soak" "$out/soak.err")" = 10 ] || fail "not one progress line a sample"

# --soak simulates its drive: with --log it stops with exit code 2.
"$bin" bench --soak 10 --log "$src/configs/scala.yaml" --out "$out/bad" >/dev/null 2>"$out/bad.err"
[ $? = 2 ] || fail "--soak with --log: exit code not 2"
grep -q "needs --scenario" "$out/bad.err" || fail "--soak with --log: $(cat "$out/bad.err")"

python3 - "$out/soak" <<'PY' || fail "soak.csv / soak.json"
import csv, json, sys

d = sys.argv[1]
rows = list(csv.DictReader(open(d + "/soak.csv")))
columns = "scans,lap,t_s,rss_kb,hwm_kb,heap_kb,processed,median_us,p99_us,max_us".split(",")
if list(rows[0].keys()) != columns:
    sys.exit("soak.csv columns: %s" % list(rows[0].keys()))
if [int(r["scans"]) for r in rows] != list(range(200, 2001, 200)):
    sys.exit("soak.csv: samples not every 200 scans: %s" % [r["scans"] for r in rows])
s = json.load(open(d + "/soak.json"))
if (s["scans"], s["every"], s["samples"], s["backend"]) != (2000, 200, 10, "tbb"):
    sys.exit("soak.json: %s" % s)
if s["laps"] != int(rows[-1]["lap"]) or s["laps"] < 3:  # urban laps are 801 scans
    sys.exit("soak.json laps %s, soak.csv last lap %s" % (s["laps"], rows[-1]["lap"]))
prev_t = -1.0
for r in rows:
    t = float(r["t_s"])
    rss, hwm, heap = int(r["rss_kb"]), int(r["hwm_kb"]), int(r["heap_kb"])
    med, p99, mx = float(r["median_us"]), float(r["p99_us"]), float(r["max_us"])
    if not (t > prev_t and 0 < rss <= hwm and heap > 0 and 0 < med <= p99 <= mx):
        sys.exit("soak.csv row out of shape: %s" % r)
    if int(r["processed"]) + s["rejected"] < 200:
        sys.exit("soak.csv: scans missing from a window: %s" % r)
    prev_t = t
if s["rss_last_kb"] != int(rows[-1]["rss_kb"]) or s["rss_peak_kb"] < s["rss_last_kb"]:
    sys.exit("soak.json RSS figures do not match soak.csv")
# Memory over the second half (scans 1,000 to 2,000, warm): RSS and the heap stay put.
half, last = rows[(len(rows) - 1) // 2], rows[-1]
rss_growth = int(last["rss_kb"]) - int(half["rss_kb"])
heap_growth = int(last["heap_kb"]) - int(half["heap_kb"])
print("second half: RSS %+d kB, heap %+d kB" % (rss_growth, heap_growth))
if rss_growth > 2048 or heap_growth > 512:
    sys.exit("memory grew over the second half: RSS %+d kB, heap %+d kB" % (rss_growth, heap_growth))
PY
echo "soak run in shape, memory bounded"
