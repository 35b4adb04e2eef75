#!/usr/bin/env bash
# `freespace bench` end to end on a short simulated drive and a recorded log: the report's
# fields, the paper's comparisons (circle exactly equal to the reference, the enhanced model
# leaving no footprint cell without update), the scaling series and their plots, usage errors.
# Usage: bench_cli_test.sh FREESPACE_BINARY DATA_DIR OUT_DIR
set -u
bin=$1 data=$2 out=$3
rm -rf "$out" && mkdir -p "$out"
fail() { echo "FAIL: $*"; exit 1; }

"$bin" bench --help | grep -q -- "--scenario" || fail "bench --help does not list --scenario"

# Exactly one of --log and --scenario.
"$bin" bench --out "$out/none" >/dev/null 2>"$out/none.err"
[ $? -eq 2 ] || fail "bench without --log or --scenario must exit 2"
grep -q "give --log FILE or --scenario NAME" "$out/none.err" || fail "no usage message"
touch "$out/empty.log"
"$bin" bench --log "$out/empty.log" --scenario urban --out "$out/both" >/dev/null 2>&1 \
  && fail "bench accepted both --log and --scenario"
"$bin" bench --scenario nowhere --out "$out/bad" >/dev/null 2>&1 && fail "unknown scenario accepted"

# A short parking drive (reversing included) with the scaling runs, host backend only.
"$bin" bench --scenario parking --scans 24 --warmup 4 --backends tbb --scaling \
  --out "$out/parking" >"$out/parking.txt" 2>"$out/parking.err" \
  || fail "bench --scenario parking failed: $(cat "$out/parking.err")"
for f in bench.json scaling_map.png scaling_points.png; do
  [ -s "$out/parking/$f" ] || fail "bench wrote no $f"
done
for f in scaling_map.png scaling_points.png; do
  head -c 8 "$out/parking/$f" | od -An -c | grep -q "P   N   G" || fail "$f is not a PNG"
done
grep -q "The paper's comparisons, this run" "$out/parking.txt" || fail "no comparison summary"
grep -q "accuracy on observed cells" "$out/parking.txt" || fail "no accuracy in the text report"
# The polygon shapes' table: a row for every stage.
sed -n '/^Polygon (median us per scan/,/^  total/p' "$out/parking.txt" >"$out/shapes.txt"
for stage in preprocess align rasterize fuse classify mask insight polygon total; do
  grep -q "^  $stage " "$out/shapes.txt" || fail "no $stage row in the polygon shapes' table"
done

python3 - "$out/parking/bench.json" <<'EOF' || fail "bench.json of the scenario run"
import json, sys
r = json.load(open(sys.argv[1]))
def check(cond, what):
    if not cond:
        sys.exit("bench.json: " + what)
check(r["scenario"]["name"] == "parking" and r["scans"] == 24, "scenario and scans")
check(r["points_per_scan"] > 2000, "a ScaLa-like scan has about 2300 points")
stages = r["pipeline"]["tbb"]["stage_us"]
for s in ("preprocess", "align", "rasterize", "fuse", "classify", "insight", "polygon", "total"):
    check(stages[s]["median"] > 0 and stages[s]["p99"] >= stages[s]["median"], "stage " + s)
m = r["sensor_model"]
e, c = m["coverage"]["enhanced"], m["coverage"]["conventional"]
check(m["coverage"]["footprint_cells"] > 0, "footprint")
# The enhanced model updates every footprint cell exactly once: no hole, Moire cell or conflict.
check(e["holes"] == 0 and e["moire"] == 0 and e["conflicts"] == 0, "enhanced holes")
check(e["mean_updates"] == 1 and e["max_updates"] == 1, "enhanced updates once")
check(c["holes"] >= 0 and 0 <= c["moire"] <= c["holes"], "conventional holes")
check(0 <= c["conflicts_free"] <= c["conflicts"], "conventional conflicts")
check(c["max_updates"] >= c["mean_updates"] >= 1, "conventional updates")
for model in ("enhanced", "conventional"):
    q = m[model]["quality"]
    check(q["scans"] == 24 and 0 < q["accuracy"] <= 1, model + " accuracy")
    check("accuracy" in q["summary"], model + " metrics summary")
    check(0 < m[model]["model_us"] < m[model]["map_us"] < m[model]["total_us"], model + " times")
check(m["model_speedup"] > 0, "model speedup")
a = r["alignment"]
# The circle alignment is exact; the rotated map is resampled every scan.
check(a["circle"]["error"]["different_fraction"] == 0, "circle differs from the reference")
check(a["circle"]["error"]["class_mismatch"] == 0, "circle class mismatch")
check(a["rotate"]["error"]["different_fraction"] > 0, "rotate shows no error")
# Both polygon shapes over the same scans in turn: each ran every one of them.
shapes = r["polygon_shape"]
for shape in ("paper", "inside"):
    check(shapes[shape]["backend"] == "tbb" and shapes[shape]["scans"] == 24, shape + " scans")
    for s in ("preprocess", "classify", "insight", "polygon", "total"):
        check(shapes[shape]["stage_us"][s]["median"] > 0, shape + " stage " + s)
check(shapes["paper"]["stage_us"]["mask"]["median"] == 0, "the paper's polygon has no mask stage")
check(shapes["inside"]["stage_us"]["mask"]["median"] > 0, "the conservative polygon's mask stage")
p = r["comparisons"]
check(len(r["load_average"]) == 2, "load average")
for k in ("enhanced_model_speedup", "enhanced_time_saved_percent", "enhanced_map_time_saved_percent",
          "circle_map_time_saved_percent", "accuracy_enhanced",
          "accuracy_conventional", "circle_different_fraction", "rotate_different_fraction",
          "circle_time_saved_percent", "pipeline_median_us", "map_exponent"):
    check(k in p, "comparisons." + k)
s = r["scaling"]
check([x["cells"] for x in s["map"]] == [150, 300, 600, 1200, 1500, 2400, 3000], "map sizes")
check(all(x["total_us"] > 0 and x["ns_per_cell"] > 0 for x in s["map"]), "map times")
check(s["map_exponent"]["tbb"]["all"] is not None, "map exponent")
for model in ("enhanced", "conventional"):
    series = [x for x in s["points"] if x["backend"] == "tbb" and x["sensor_model"] == model]
    pts = [x["points_per_scan"] for x in series]
    check(len(pts) == 5 and all(a < b for a, b in zip(pts, pts[1:])), "points not increasing")
    check(pts[0] == 500 and pts[-1] == 8000, "points 500 .. 8000")
    check(all(x["total_us"] > 0 for x in series), "points times")
conv = [x["model_us"] for x in s["points"] if x["sensor_model"] == "conventional"]
check(conv[-1] > conv[0], "conventional model time does not grow with the points")
EOF

# A recorded log: the same comparisons without truth; --json prints the report.
log="$data/carmen/intel-corrected.log"
if [ ! -f "$log" ]; then
  echo "SKIP: $log not found (set FREESPACE_DATA_DIR); the log case did not run"
  exit 0
fi
"$bin" bench --log "$log" --scans 40 --warmup 5 --json --out "$out/intel" \
  >"$out/intel.json" 2>"$out/intel.err" || fail "bench --log failed: $(cat "$out/intel.err")"
cmp -s "$out/intel.json" "$out/intel/bench.json" || fail "--json output differs from bench.json"
python3 - "$out/intel.json" <<'EOF' || fail "bench.json of the log run"
import json, sys
r = json.load(open(sys.argv[1]))
def check(cond, what):
    if not cond:
        sys.exit("bench.json: " + what)
check(r["log"].endswith("intel-corrected.log") and "scenario" not in r, "source")
check("quality" not in r["sensor_model"]["enhanced"], "quality without truth")
check(r["alignment"]["circle"]["error"]["different_fraction"] == 0, "circle error")
check(r["sensor_model"]["coverage"]["enhanced"]["holes"] == 0, "enhanced holes")
tbb = r["pipeline"]["tbb"]
check(tbb["stage_us"]["total"]["median"] > 0, "tbb pipeline")
ocl = r["pipeline"].get("opencl", {})
if "unavailable" not in ocl:
    check(ocl["stage_us"]["total"]["median"] > 0, "opencl pipeline")
    check(ocl["opencl_wait"] == "auto" and ocl["opencl_spin_us"] == 250, "opencl wait mode")
    check(r["comparisons"]["opencl_over_tbb_total"] > 0, "opencl over tbb")
check("opencl_wait" not in tbb, "no wait mode for tbb")
EOF

# The text report names the wait mode of the OpenCL run, here the one given on the command line.
"$bin" bench --log "$log" --scans 12 --warmup 2 --backends opencl --opencl-wait spin \
  --out "$out/spin" >"$out/spin.txt" 2>"$out/spin.err" || fail "bench --opencl-wait spin failed"
if grep -q "^freespace bench: opencl: " "$out/spin.err"; then
  echo "SKIP: no OpenCL device, the wait mode in the report was not checked: $(cat "$out/spin.err")"
else
  grep -q "^  opencl: .*, wait spin (" "$out/spin.txt" || fail "report does not name the wait mode"
fi
echo "PASS"
