#!/usr/bin/env bash
# The `freespace` command line on real and bad input: outputs, counts, exit codes.
# Usage: cli_test.sh FREESPACE_BINARY DATA_DIR OUT_DIR
set -u
bin=$1 data=$2 out=$3
rm -rf "$out" && mkdir -p "$out"
fail() { echo "FAIL: $*"; exit 1; }

"$bin" --help | grep -q "run" || fail "--help does not list run"
"$bin" run --help | grep -q -- "--strict" || fail "run --help does not document --strict"
"$bin" --version | grep -qx "freespace [0-9]*\.[0-9]*\.[0-9]*" || fail "--version: $("$bin" --version)"

log="$data/carmen/intel-corrected.log"
if [ ! -f "$log" ]; then
  echo "SKIP: $log not found (set FREESPACE_DATA_DIR); the recorded-log CLI cases did not run"
  exit 0
fi

# A real log: every scan has a line; its 4 backwards timestamps are clock jitter, reported.
"$bin" run --log "$log" --out "$out/intel" --snapshot-every 300 --quiet 2>"$out/intel.err" \
  || fail "run on intel-corrected.log failed: $(cat "$out/intel.err")"
[ "$(wc -l <"$out/intel/polygons.jsonl")" -eq 910 ] || fail "expected 910 polygon lines"
grep -q '"scans": 910' "$out/intel/summary.json" || fail "summary scans"
grep -q '"skipped": 0' "$out/intel/summary.json" || fail "summary skipped"
grep -q '"timestamp_jitter": 4' "$out/intel/summary.json" || fail "summary timestamp_jitter"
grep -q '"median"' "$out/intel/summary.json" || fail "summary stage_us"
ls "$out"/intel/snapshot_*.png >/dev/null 2>&1 || fail "no PNG snapshots"
grep -q '"polygon_status":"ok","polygon":\[\[' "$out/intel/polygons.jsonl" || fail "polygon field"
# Where the opening (1.8 m) leaves nothing free around the sensor in the lab's corridors: no
# polygon, and a status that says so; never vertices with that status.
grep -q '"polygon_status":"no_free_space","polygon":\[\]' "$out/intel/polygons.jsonl" \
  || fail "no scan with an empty polygon and its status"
if grep '"polygon_status":"no_free_space"' "$out/intel/polygons.jsonl" \
  | grep -qv '"polygon":\[\]'; then
  fail "a scan without free space has vertices"
fi
grep -q "clock jitter" "$out/intel.err" || fail "backwards timestamps not reported"
# A larger step back than alignment.time_jitter_s rejects the scan.
printf 'alignment:\n  time_jitter_s: 0.1\n' >"$out/strict-clock.yaml"
"$bin" run --log "$log" --out "$out/intel-clock" --config "$out/strict-clock.yaml" --quiet \
  2>"$out/intel-clock.err" || fail "run with time_jitter_s 0.1 failed"
grep -q '"timestamp_not_increasing"' "$out/intel-clock/summary.json" || fail "no rejected scans"
grep -q "more than alignment.time_jitter_s" "$out/intel-clock.err" || fail "rejection message"
# A sensor section replaces the log's sensor whole, a partial one too: a note says so, and
# none without a section.
printf 'sensor:\n  mount_x_m: 0.1\n' >"$out/partial-sensor.yaml"
"$bin" run --log "$log" --out "$out/intel-partial" --config "$out/partial-sensor.yaml" \
  --max-scans 3 --quiet 2>"$out/intel-partial.err" || fail "run with a partial sensor failed"
grep -qF "the config's sensor section replaces the log's sensor (1 layer(s), -90 .. 89 deg" \
  "$out/intel-partial.err" || fail "no note of the replaced sensor: $(cat "$out/intel-partial.err")"
grep -q "replaces the log's sensor" "$out/intel.err" && fail "a note without a sensor section"

# The last scan rejected (the first again, 200 s back): the closing snapshot is the last
# processed scan's (59), not the rejected one's.
grep '^FLASER' "$log" | head -60 >"$out/last-rejected.log"
grep -m 1 '^FLASER' "$log" >>"$out/last-rejected.log"
"$bin" run --log "$out/last-rejected.log" --out "$out/last-rejected" --snapshot-every 0 --quiet \
  2>/dev/null || fail "run on last-rejected.log failed"
[ "$(cd "$out/last-rejected" && ls snapshot_*.png)" = "snapshot_000059.png" ] \
  || fail "closing snapshot: $(ls "$out/last-rejected")"

# An earlier run's files in --out go first (said), so that none stands beside this run's.
touch "$out/last-rejected/snapshot_999999.png" "$out/last-rejected/polygons.geojsonl"
"$bin" run --log "$out/last-rejected.log" --out "$out/last-rejected" --snapshot-every 0 --quiet \
  2>"$out/rerun.err" || fail "rerun into the same --out failed"
grep -q "removed 5 file(s) of an earlier run" "$out/rerun.err" || fail "$(cat "$out/rerun.err")"
[ "$(cd "$out/last-rejected" && ls | tr '\n' ' ')" = "polygons.jsonl snapshot_000059.png summary.json " ] \
  || fail "after the rerun: $(ls "$out/last-rejected")"

# A malformed line: reported with file and line, skipped and counted; --strict stops.
head -n 40 "$log" >"$out/bad.log"
echo "FLASER 180 1.0 2.0 3.0" >>"$out/bad.log"
sed -n '41,400p' "$log" >>"$out/bad.log"
"$bin" run --log "$out/bad.log" --out "$out/bad" --quiet 2>"$out/bad.err" || fail "bad log run"
grep -q "bad.log:41: FLASER: truncated line" "$out/bad.err" || fail "truncated line not reported"
grep -q '"malformed_lines": 1' "$out/bad/summary.json" || fail "malformed line not counted"
"$bin" run --log "$out/bad.log" --out "$out/bad-strict" --strict --quiet 2>/dev/null
[ $? -eq 1 ] || fail "--strict must exit 1 on bad input"

# A bad config value: exit 2 and a message naming the field and the value.
printf 'map:\n  resolution_m: -0.5\n' >"$out/bad.yaml"
"$bin" run --log "$log" --out "$out/cfg" --config "$out/bad.yaml" 2>"$out/cfg.err"
[ $? -eq 2 ] || fail "bad config must exit 2"
grep -q "map.resolution_m = -0.5" "$out/cfg.err" || fail "config error does not name the field"
# --set: one field over the config file; a bad one exits 2 naming the setting.
"$bin" run --log "$log" --out "$out/set" --config "$(dirname "$0")/../configs/indoor.yaml" \
  --set polygon.max_vertices=5 \
  --max-scans 30 --snapshot-every 0 --quiet 2>/dev/null || fail "run with --set failed"
grep -q '"max_vertices": [3-5],' "$out/set/summary.json" || fail "--set polygon.max_vertices=5 not used"
"$bin" run --log "$log" --out "$out/set-bad" --set polygon.max_vertices=010 2>"$out/set.err"
[ $? -eq 2 ] || fail "a bad --set must exit 2"
grep -q "^freespace run: --set polygon.max_vertices=010: .*not a valid integer" "$out/set.err" ||
  fail "a bad --set is not named: $(cat "$out/set.err")"

# The backends: --backend opencl and --backend tbb write identical polygons on the same log.
# Without a usable OpenCL device (or an OpenCL build) the comparison is skipped, saying why.
"$bin" run --log "$log" --out "$out/tbb" --backend tbb --snapshot-every 0 --quiet 2>/dev/null \
  || fail "run --backend tbb failed"
"$bin" run --log "$log" --out "$out/opencl" --backend opencl --snapshot-every 0 --quiet \
  2>"$out/opencl.err"
rc=$?
if [ $rc -eq 0 ]; then
  grep -q "backend opencl: " "$out/opencl.err" || fail "run --backend opencl does not name its device"
  cmp "$out/tbb/polygons.jsonl" "$out/opencl/polygons.jsonl" \
    || fail "--backend opencl and --backend tbb wrote different polygons.jsonl"
  echo "cli: --backend opencl and --backend tbb wrote identical polygons.jsonl"
  "$bin" run --log "$log" --out "$out/opencl-block" --backend opencl --opencl-wait block \
    --snapshot-every 0 --quiet 2>/dev/null || fail "run --opencl-wait block failed"
  cmp "$out/tbb/polygons.jsonl" "$out/opencl-block/polygons.jsonl" \
    || fail "--opencl-wait block wrote different polygons.jsonl"
  "$bin" run --log "$log" --out "$out/auto" --backend auto --max-scans 3 --quiet \
    2>"$out/auto.err" || fail "run --backend auto failed"
  grep -q "backend auto: using opencl: " "$out/auto.err" \
    || fail "--backend auto does not say it took opencl: $(cat "$out/auto.err")"
  # `devices` marks the device auto took, and --check builds the kernels on it.
  taken=$(sed -n 's/^freespace: backend auto: using opencl: //p' "$out/auto.err")
  "$bin" devices --check >"$out/devices.txt" 2>"$out/devices.err" \
    || fail "devices --check failed: $(cat "$out/devices.err")"
  grep '^  \* ' "$out/devices.txt" | grep -qF "\"$taken\"" \
    || fail "devices does not mark \"$taken\": $(cat "$out/devices.txt")"
  grep -q "^check: the kernels built for a 300 x 300 map" "$out/devices.txt" \
    || fail "devices --check did not build: $(cat "$out/devices.txt")"
  "$bin" devices --json >"$out/devices.json" || fail "devices --json failed"
  python3 - "$out/devices.json" "$taken" <<'EOF' || fail "devices --json"
import json, sys
r = json.load(open(sys.argv[1]))
chosen = [d["name"] for p in r["platforms"] for d in p["devices"] if d["chosen"]]
assert chosen == [sys.argv[2]] and r["error"] is None and r["opencl_built"], r
assert r["device_filter"] == {"value": "", "from": "config"}, r
EOF
  FREESPACE_OPENCL_DEVICE=no-such-device "$bin" devices >"$out/devices-none.txt" \
    2>"$out/devices-none.err"
  [ $? -eq 2 ] || fail "devices with no matching device must exit 2"
  grep -q "no usable OpenCL device matches platform \"\" (config) and device \"no-such-device\" (FREESPACE_OPENCL_DEVICE)" \
    "$out/devices-none.err" || fail "devices does not say why: $(cat "$out/devices-none.err")"
  grep -q '^  \* ' "$out/devices-none.txt" && fail "devices marked a device that does not match"
  # PoCL's basic device: `devices` says how to list it, lists it with POCL_DEVICES, and a run on
  # it writes the same polygons.jsonl as tbb.
  if grep -q '^  platform "Portable Computing Language"' "$out/devices.txt" \
    && grep -q '"pthread-' "$out/devices.txt" && ! grep -q '"basic-' "$out/devices.txt"; then
    grep -q 'is listed with POCL_DEVICES="pthread basic"' "$out/devices.txt" \
      || fail "devices does not say how to list PoCL's basic device: $(cat "$out/devices.txt")"
    POCL_DEVICES="pthread basic" "$bin" devices >"$out/devices-basic.txt" \
      || fail "devices with POCL_DEVICES=\"pthread basic\" failed"
    grep -q '^  . cpu "basic-' "$out/devices-basic.txt" \
      || fail "POCL_DEVICES=\"pthread basic\" does not list basic: $(cat "$out/devices-basic.txt")"
    grep -q 'is listed with POCL_DEVICES' "$out/devices-basic.txt" \
      && fail "devices says how to list the basic device although it is listed"
    POCL_DEVICES="pthread basic" FREESPACE_OPENCL_DEVICE=basic- "$bin" run --log "$log" \
      --out "$out/opencl-basic" --backend opencl --snapshot-every 0 --quiet \
      2>"$out/opencl-basic.err" || fail "run on PoCL's basic device failed: $(cat "$out/opencl-basic.err")"
    grep -q "backend opencl: basic-" "$out/opencl-basic.err" \
      || fail "run did not take PoCL's basic device: $(cat "$out/opencl-basic.err")"
    cmp "$out/tbb/polygons.jsonl" "$out/opencl-basic/polygons.jsonl" \
      || fail "PoCL's basic device and --backend tbb wrote different polygons.jsonl"
    echo "cli: PoCL's basic device and --backend tbb wrote identical polygons.jsonl"
    # Split over two basic devices (--opencl-devices 2): the same polygons again; with one basic
    # device listed, a setup error that says how many there are.
    POCL_DEVICES="basic basic" FREESPACE_OPENCL_DEVICE=basic- "$bin" run --log "$log" \
      --out "$out/opencl-split" --backend opencl --opencl-devices 2 --snapshot-every 0 --quiet \
      2>"$out/opencl-split.err" || fail "run --opencl-devices 2 failed: $(cat "$out/opencl-split.err")"
    grep -q "backend opencl: basic-.* x 2" "$out/opencl-split.err" \
      || fail "run --opencl-devices 2 does not name two devices: $(cat "$out/opencl-split.err")"
    cmp "$out/tbb/polygons.jsonl" "$out/opencl-split/polygons.jsonl" \
      || fail "--opencl-devices 2 and --backend tbb wrote different polygons.jsonl"
    echo "cli: --opencl-devices 2 and --backend tbb wrote identical polygons.jsonl"
    POCL_DEVICES="pthread basic" FREESPACE_OPENCL_DEVICE=basic- "$bin" run --log "$log" \
      --out "$out/opencl-split1" --backend opencl --opencl-devices 2 --quiet \
      2>"$out/opencl-split1.err"
    rc=$?
    [ $rc -eq 2 ] || fail "--opencl-devices 2 with one basic device: exit code $rc, expected 2"
    grep -q 'opencl_devices = 2 (config) needs 2 devices named "basic-.*; it lists 1 .*POCL_DEVICES="basic basic"' \
      "$out/opencl-split1.err" \
      || fail "--opencl-devices 2 with one basic device: $(cat "$out/opencl-split1.err")"
    echo "cli: --opencl-devices 2 with one basic device: $(head -c 200 "$out/opencl-split1.err")"
  else
    echo "SKIP: PoCL's basic device: no PoCL platform listing its pthread device alone here" \
      "(POCL_DEVICES=${POCL_DEVICES:-unset})"
  fi
elif [ $rc -eq 2 ] && grep -q "backend opencl" "$out/opencl.err"; then
  echo "SKIP: backend comparison: --backend opencl is not available here: $(grep -m1 "backend opencl" "$out/opencl.err")"
else
  fail "run --backend opencl failed with exit code $rc: $(cat "$out/opencl.err")"
fi

# No OpenCL platform (an empty ICD vendor directory): opencl is a setup error naming what is
# missing, auto falls back to tbb and says so.
mkdir -p "$out/no-icd"
OCL_ICD_VENDORS="$out/no-icd" "$bin" run --log "$log" --out "$out/no-icd-run" --backend opencl \
  --max-scans 3 --quiet 2>"$out/no-icd.err"
rc=$?
[ $rc -eq 2 ] || fail "--backend opencl without a platform must exit 2, got $rc"
grep -q -e "no OpenCL platform (ICD loader found none)" -e "has no OpenCL backend" \
  "$out/no-icd.err" || fail "no-platform error not explained: $(cat "$out/no-icd.err")"
OCL_ICD_VENDORS="$out/no-icd" "$bin" run --log "$log" --out "$out/no-icd-auto" --backend auto \
  --max-scans 3 --quiet 2>"$out/no-icd-auto.err" || fail "--backend auto without OpenCL failed"
grep -q "backend auto: .*using tbb" "$out/no-icd-auto.err" \
  || fail "--backend auto does not say it took tbb: $(cat "$out/no-icd-auto.err")"
OCL_ICD_VENDORS="$out/no-icd" "$bin" devices --json >"$out/no-icd-devices.json" 2>/dev/null
[ $? -eq 2 ] || fail "devices without a platform must exit 2"
python3 - "$out/no-icd-devices.json" <<'EOF' || fail "devices --json without a platform"
import json, sys
r = json.load(open(sys.argv[1]))
assert r["platforms"] == [] and ("ICD loader found none" in r["error"] or not r["opencl_built"]), r
EOF

echo "cli: all cases passed"
