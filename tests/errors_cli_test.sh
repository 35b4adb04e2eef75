#!/usr/bin/env bash
# The error contract of the `freespace` command (docs/behaviour.md): an output that cannot be
# written is an error naming the file with exit code 2, and nothing is claimed written that was
# not; usage errors (CLI11's included) exit 2.
# Usage: errors_cli_test.sh FREESPACE_BINARY OUT_DIR
set -u
bin=$1 out=$2
rm -rf "$out" && mkdir -p "$out"
fail() { echo "FAIL: $*"; exit 1; }
# The full-disk cases write to /dev/full; without it they are skipped, said, and the rest run.
full=1
[ -w /dev/full ] || { echo "SKIP: /dev/full is not writable here: the full-disk cases"; full=0; }

# expect CODE NAME CMD...: runs CMD, which must exit CODE; its stderr+stdout go to $out/NAME.txt.
expect() {
  local code=$1 name=$2
  shift 2
  "$@" >"$out/$name.txt" 2>&1
  local rc=$?
  [ $rc -eq "$code" ] || fail "$name: exit code $rc, expected $code: $(head -c 600 "$out/$name.txt")"
}
# names NAME TEXT: the output of case NAME mentions TEXT and claims nothing written.
names() {
  grep -qF -- "$2" "$out/$1.txt" || fail "$1: does not name $2: $(head -c 600 "$out/$1.txt")"
  grep -q "wrote" "$out/$1.txt" && fail "$1: claims files written: $(cat "$out/$1.txt")"
  return 0
}

"$bin" simulate --scenario parking --duration 1 --seed 3 --out "$out/sim" 2>/dev/null \
  || fail "simulate failed"
log="$out/sim/sim.fslog"
run() { "$bin" run --log "$log" --backend tbb --quiet "$@"; }

# run: polygons.jsonl on a full disk, summary.json and a snapshot blocked by a directory.
if [ $full -eq 1 ]; then
  mkdir -p "$out/full" && ln -s /dev/full "$out/full/polygons.jsonl"
  expect 2 run-full run --out "$out/full"
  names run-full "$out/full/polygons.jsonl: write failed: No space left on device"
fi
mkdir -p "$out/summary-dir/summary.json"
expect 2 run-summary run --out "$out/summary-dir"
names run-summary "$out/summary-dir/summary.json: cannot create"
mkdir -p "$out/png-dir/snapshot_000000.png"
expect 2 run-png run --out "$out/png-dir" --snapshot-every 1
names run-png "$out/png-dir/snapshot_000000.png: cannot write PNG"
# An output folder that cannot be created.
touch "$out/a-file"
expect 2 run-outdir run --out "$out/a-file/sub"
names run-outdir "$out/a-file/sub: cannot create directory"
expect 0 run-ok run --out "$out/ok"
grep -q "wrote $out/ok/polygons.jsonl, summary.json" "$out/run-ok.txt" || fail "run-ok: no closing line"

# An output that is an input file (through a link or another path too) is refused before
# anything is written, the input left as it was.
cp "$log" "$out/in.fslog" && ln -s "$out/in.fslog" "$out/in-link.fslog"
printf 'polygon:\n  max_vertices: 64\n' >"$out/in.yaml"
sum_before=$(cat "$out/in.fslog" "$out/in.yaml" | md5sum)
expect 2 run-bag-is-log "$bin" run --log "$out/in-link.fslog" --out "$out/same" \
  --out-bag "$out/./in.fslog"
names run-bag-is-log "--out-bag would write $out/./in.fslog, the file --log reads"
expect 2 run-map-is-config run --config "$out/in.yaml" --out "$out/same" --save-map "$out/in"
names run-map-is-config "--save-map would write $out/in.yaml, the file --config reads"
# A log in --out under a name of the run's files: not removed as an earlier run's.
mkdir -p "$out/in-out" && cp "$log" "$out/in-out/polygons.jsonl"
expect 2 run-log-in-out "$bin" run --log "$out/in-out/polygons.jsonl" --out "$out/in-out"
names run-log-in-out "--out would write $out/in-out/polygons.jsonl, the file --log reads"
cmp -s "$log" "$out/in-out/polygons.jsonl" || fail "the log in --out was changed"
# A config in --out named like a snapshot, which a run removes as an earlier run's.
mkdir -p "$out/snap-out" && cp "$out/in.yaml" "$out/snap-out/snapshot_000001.png"
expect 2 run-config-as-snapshot run --config "$out/snap-out/snapshot_000001.png" --out "$out/snap-out"
names run-config-as-snapshot "--out would write $out/snap-out/snapshot_000001.png, the file --config"
cmp -s "$out/in.yaml" "$out/snap-out/snapshot_000001.png" || fail "the config in --out was changed"
# The demo's own config.yaml given back as its --config, into the same --out.
mkdir -p "$out/demo-again" && cp "$out/in.yaml" "$out/demo-again/config.yaml"
expect 2 demo-config-in-out "$bin" demo --duration 1 --config "$out/demo-again/config.yaml" \
  --out "$out/demo-again" --quiet
names demo-config-in-out "--out would write $out/demo-again/config.yaml, the file --config reads"
cmp -s "$out/in.yaml" "$out/demo-again/config.yaml" || fail "the demo's --config was changed"
expect 2 demo-map-is-config "$bin" demo --duration 1 --config "$out/in.yaml" --out "$out/same" \
  --save-map "$out/in" --quiet
names demo-map-is-config "--save-map would write $out/in.yaml, the file --config reads"
[ "$(cat "$out/in.fslog" "$out/in.yaml" | md5sum)" = "$sum_before" ] || fail "an input was changed"
[ ! -e "$out/same" ] || fail "a refused run created its --out folder"

# A log that is a pipe or a device: refused at once with the reason (reading a FIFO would wait
# for a writer; a pipe cannot be read twice, as format detection does).
mkfifo "$out/log.fifo"
expect 2 run-fifo timeout 60 "$bin" run --log "$out/log.fifo" --out "$out/fifo"
names run-fifo "$out/log.fifo: a pipe or a device, not a file"
expect 2 eval-devnull timeout 60 "$bin" eval --log /dev/null --truth "$out/sim/truth.json" \
  --out "$out/devnull"
names eval-devnull "/dev/null: a pipe or a device, not a file"

# A log whose clock never advances: the stall is said once, and every scan is used.
awk '$1=="SCAN"{$2="5.0"} {print}' "$log" >"$out/stalled.fslog"
"$bin" run --log "$out/stalled.fslog" --backend tbb --quiet --out "$out/stalled" \
  2>"$out/stalled.txt" || fail "run on a stalled clock failed: $(cat "$out/stalled.txt")"
[ "$(grep -c "the clock has stalled" "$out/stalled.txt")" -eq 1 ] \
  || fail "stalled clock: expected one message: $(cat "$out/stalled.txt")"
grep -q '"scans": 26,' "$out/stalled/summary.json" || fail "stalled clock: not every scan used"
grep -q '"clock_stalled": 24,' "$out/stalled/summary.json" || fail "stalled clock: count"
grep -q '"timestamp_jitter": 1,' "$out/stalled/summary.json" || fail "stalled clock: jitter"
expect 1 stalled-strict "$bin" run --log "$out/stalled.fslog" --backend tbb --quiet --strict \
  --out "$out/stalled-strict"

# Extreme but finite poses and times: rejected with their reason, and every line written is
# valid JSON.
awk '$1=="SCAN" && $2=="0.400000"{$3="1e300"} $1=="SCAN" && $2=="0.480000"{$2="1e307"} {print}' \
  "$log" >"$out/extreme.fslog"
"$bin" run --log "$out/extreme.fslog" --backend tbb --quiet --out "$out/extreme" \
  2>"$out/extreme.txt" || fail "run on extreme values failed: $(cat "$out/extreme.txt")"
grep -q '"pose_out_of_range": 1' "$out/extreme/summary.json" || fail "extreme pose not rejected"
grep -q '"timestamp_out_of_range": 1' "$out/extreme/summary.json" || fail "extreme time not rejected"
/usr/bin/python3 -c '
import json, sys
for n, line in enumerate(open(sys.argv[1]), 1):
    json.loads(line, parse_constant=lambda c: sys.exit("line %d: %s" % (n, c)))
' "$out/extreme/polygons.jsonl" || fail "extreme: polygons.jsonl is not valid JSON"

# simulate, eval and demo: each output on a full disk or behind a directory.
if [ $full -eq 1 ]; then
  mkdir -p "$out/sim-full" && ln -s /dev/full "$out/sim-full/sim.fslog"
  expect 2 simulate-full "$bin" simulate --scenario parking --duration 1 --out "$out/sim-full"
  names simulate-full "$out/sim-full/sim.fslog: write failed: No space left on device"
fi
mkdir -p "$out/sim-dir/truth.json"
expect 2 simulate-dir "$bin" simulate --scenario parking --duration 1 --out "$out/sim-dir"
names simulate-dir "$out/sim-dir/truth.json: cannot create: Is a directory"
mkdir -p "$out/map-dir/m.pgm"
expect 2 map-dir run --out "$out/map-dir/o" --save-map "$out/map-dir/m"
names map-dir "$out/map-dir/m.pgm: cannot create: Is a directory"
mkdir -p "$out/eval-dir/eval.json"
expect 2 eval-dir "$bin" eval --log "$log" --truth "$out/sim/truth.json" --out "$out/eval-dir" \
  --backend tbb
names eval-dir "$out/eval-dir/eval.json: cannot create"
demo() { "$bin" demo --scenario parking --duration 1 --backend tbb --quiet "$@"; }
mkdir -p "$out/demo-config/config.yaml"
expect 2 demo-config demo --out "$out/demo-config"
names demo-config "$out/demo-config/config.yaml: cannot create"
if [ $full -eq 1 ]; then
  mkdir -p "$out/demo-full" && ln -s /dev/full "$out/demo-full/polygons.jsonl"
  expect 2 demo-full demo --out "$out/demo-full" --no-video
  names demo-full "$out/demo-full/polygons.jsonl: write failed"
fi
mkdir -p "$out/demo-avi/demo.avi"
expect 2 demo-avi demo --out "$out/demo-avi"
names demo-avi "$out/demo-avi/demo.avi"

# Usage errors exit 2, CLI11's checks included; --help exits 0.
expect 2 no-log "$bin" run --out "$out/x"
expect 2 missing-log "$bin" run --log "$out/no-such.log" --out "$out/x"
names missing-log "no-such.log"
expect 2 dir-log "$bin" run --log "$out" --out "$out/x"
expect 2 unknown-option "$bin" run --log "$log" --no-such-option
expect 2 bad-value "$bin" run --log "$log" --snapshot-every -3
expect 2 no-command "$bin"
expect 0 help "$bin" run --help

# Options that would be read otherwise than written, or not at all, are usage errors: an integer
# in another base or wrapped into an unsigned one, a number that is not finite, a negative count,
# a seed or scenario given twice, options the chosen mode does not read.
expect 2 octal-seed "$bin" simulate --seed 010 --out "$out/x"
names octal-seed "'010' is not a non-negative integer in decimal digits"
expect 2 negative-seed "$bin" simulate --seed -1 --out "$out/x"
expect 2 hex-count "$bin" run --log "$log" --max-scans 0x10 --out "$out/x"
expect 2 negative-count "$bin" run --log "$log" --max-scans -5 --out "$out/x"
expect 2 nan-duration "$bin" simulate --duration nan --out "$out/x"
names nan-duration "'nan' is not a finite number"
expect 2 inf-bias "$bin" simulate --yaw-rate-bias inf --out "$out/x"
expect 2 seed-twice "$bin" eval --seeds 1-2,2 --duration 0.1 --out "$out/x"
names seed-twice "seed 2 given twice"
expect 2 scenario-twice "$bin" eval --seeds 1 --scenarios urban,urban --duration 0.1 --out "$out/x"
expect 2 scenarios-alone "$bin" demo --scenarios highway --duration 0.1 --out "$out/x"
names scenarios-alone "--scenarios requires --seeds"
expect 2 seeds-and-seed "$bin" eval --seeds 1 --seed 9 --duration 0.1 --out "$out/x"
names seeds-and-seed "one drive: --seeds 9"
expect 2 empty-seeds "$bin" eval --seeds '' --out "$out/x"
names empty-seeds "--seeds: empty"
expect 2 eval-seed "$bin" eval --seed 3 --out "$out/x"
names eval-seed "one drive: --seeds 3"
expect 2 eval-scenario "$bin" eval --scenario parking --out "$out/x"
names eval-scenario "--scenario requires --seeds"
expect 2 log-and-sim "$bin" eval --log "$log" --truth "$out/sim/truth.json" --duration 0.2 \
  --out "$out/x"
names log-and-sim "--log excludes --duration"
expect 2 bench-log-and-sim "$bin" bench --log "$log" --seed 7 --out "$out/x"
expect 2 rig-soak "$bin" bench --scenario urban --rig surround --soak 50 --out "$out/x"
names rig-soak "without --scaling or --soak"
expect 2 rig-sensor-set "$bin" bench --scenario urban --rig surround --duration 1 \
  --set sensor.layers=2 --out "$out/x"
names rig-sensor-set "the simulated rig's own scanners"
grep -q "median_us" "$out/rig-sensor-set.txt" && fail "bench --rig printed its table, then refused"
expect 2 topic-not-bag run --out "$out/x" --scan-topic /scan
names topic-not-bag "--scan-topic does not apply to a freespace log"
expect 2 layers-not-kitti run --out "$out/x" --kitti-layers=-1,1
names layers-not-kitti "--kitti-layers does not apply to a freespace log"
expect 2 frame-without-bag run --out "$out/x" --out-bag-frame map
expect 2 map-prefix-folder run --out "$out/x" --save-map "$out/maps/"
names map-prefix-folder "names no file"
expect 2 seeds-leading-zero "$bin" eval --seeds 007 --duration 0.1 --out "$out/x"
expect 2 seeds-and-video "$bin" demo --seeds 1 --video-every 4 --duration 0.1 --out "$out/x"
expect 2 sensor-set-seeds "$bin" eval --seeds 1 --set sensor.max_range_m=5 --duration 0.1 \
  --out "$out/x"
names sensor-set-seeds "each drive's scanner is the sensor"
printf 'sensor:\n  layers: 4\n' >"$out/sensor.yaml"
expect 2 sensor-set-rig "$bin" eval --seeds 1 --rig surround --config "$out/sensor.yaml" \
  --set sensor.max_range_m=50 --duration 0.1 --out "$out/x"
names sensor-set-rig "the scanners of --rig surround are the sensors of its drives"
expect 2 demo-sensor-set-rig "$bin" demo --rig surround --config "$out/sensor.yaml" \
  --set sensor.max_range_m=50 --duration 0.1 --out "$out/x"
names demo-sensor-set-rig "the scanners of --rig surround are the sensors of its drive"
# A simulated rig of several scanners brings its vehicle too (refused before any file is made);
# a config with another number of sensors than the drive's scanners is refused.
rm -rf "$out/rig-set"
expect 2 demo-rig-set-rig "$bin" demo --rig surround --set rig.footprint_length_m=0 \
  --duration 0.1 --out "$out/rig-set"
names demo-rig-set-rig "the vehicle of --rig surround is its drives' rig section"
[ -e "$out/rig-set" ] && fail "demo refused its config after making $out/rig-set"
expect 2 eval-rig-set-rig "$bin" eval --seeds 1 --rig surround --set rig.reference_x_m=0 \
  --duration 0.1 --out "$out/x"
names eval-rig-set-rig "the vehicle of --rig surround is its drives' rig section"
expect 2 demo-rig-count "$bin" demo --rig front --config "$(dirname "$0")/../configs/surround.yaml" \
  --duration 0.1 --out "$out/x"
names demo-rig-count "the drive's rig 'front' has 1 scanner(s), the config 4 sensors"

echo "errors_cli: all cases passed"
