#!/usr/bin/env bash
# The simulator's commands end to end: `simulate` writes logs and truth that `run` and `eval`
# read, `demo` writes every output, bad input gives the documented exit codes.
# Usage: sim_cli_test.sh FREESPACE_BINARY OUT_DIR
set -u
bin=$1 out=$2
src=$(cd "$(dirname "$0")/.." && pwd)
rm -rf "$out" && mkdir -p "$out"
fail() { echo "FAIL: $*"; exit 1; }

for command in demo simulate eval; do
  "$bin" --help | grep -q "$command" || fail "--help does not list $command"
done

# simulate: 1 s of parking is 26 scans; the logs read back through `run` like any log.
"$bin" simulate --scenario parking --duration 1 --seed 5 --out "$out/sim" 2>"$out/sim.err" \
  || fail "simulate failed: $(cat "$out/sim.err")"
for f in sim.fslog sim.clf truth.json; do [ -s "$out/sim/$f" ] || fail "simulate wrote no $f"; done
[ "$(grep -c '^SCAN' "$out/sim/sim.fslog")" -eq 26 ] || fail "expected 26 SCAN lines"
grep -q '"format": "freespace-truth"' "$out/sim/truth.json" || fail "truth format tag"
"$bin" run --log "$out/sim/sim.fslog" --out "$out/run" --quiet 2>/dev/null || fail "run on sim.fslog"
[ "$(wc -l <"$out/run/polygons.jsonl")" -eq 26 ] || fail "run: expected 26 polygon lines"
"$bin" run --log "$out/sim/sim.clf" --out "$out/run-clf" --quiet 2>/dev/null || fail "run on sim.clf"
[ "$(wc -l <"$out/run-clf/polygons.jsonl")" -eq 26 ] || fail "run on sim.clf: expected 26 lines"

# run, interrupted: Ctrl-C (SIGINT) or SIGTERM once the run has written its first polygon
# lines stops a run of a 30 s drive (a snapshot a scan, several seconds): the run ends by the
# signal, every polygon line is whole JSON, one per processed scan as summary.json counts, and
# summary.json names the signal. A SIGINT the run was started ignoring (nohup) stays ignored:
# that run goes to the end.
"$bin" simulate --scenario parking --duration 30 --seed 5 --out "$out/long" 2>"$out/long.err" \
  || fail "simulate 30 s failed: $(cat "$out/long.err")"
python3 - "$bin" "$out" <<'PY' || fail "an interrupted run"
import json, os, re, signal, subprocess, sys, time

bin, out = sys.argv[1:3]

def run(name, sig, ignore=False, every="1"):
    """Starts a run, sends `sig` once polygons.jsonl holds a whole line; its exit status (the
    negated signal that ended it), summary and stderr."""
    polygons = out + "/" + name + "/polygons.jsonl"
    disposition = signal.SIG_IGN if ignore else signal.SIG_DFL
    child = subprocess.Popen(
        [bin, "run", "--log", out + "/long/sim.fslog", "--out", out + "/" + name,
         "--snapshot-every", every, "--quiet"], stderr=subprocess.PIPE, text=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, disposition))
    deadline = time.monotonic() + 60
    while child.poll() is None and time.monotonic() < deadline:
        if os.path.exists(polygons) and b"\n" in open(polygons, "rb").read():
            break
        time.sleep(0.005)
    if child.poll() is not None:
        sys.exit("FAIL: %s: the run ended (%d) before the signal" % (name, child.returncode))
    child.send_signal(sig)
    said = child.stderr.read()
    code = child.wait()
    summary = json.load(open(out + "/" + name + "/summary.json"))
    lines = open(polygons).read().split("\n")
    if lines[-1] != "":
        sys.exit("FAIL: %s: the last polygon line is cut: %r" % (name, lines[-1][-40:]))
    scans = [json.loads(line)["scan"] for line in lines[:-1]]
    if len(scans) != summary["scans"]:
        sys.exit("FAIL: %s: %d lines, summary says %d scans" % (name, len(scans), summary["scans"]))
    return code, summary, said

total = sum(1 for line in open(out + "/long/sim.fslog") if line.startswith("SCAN"))
for sig, name in ((signal.SIGINT, "SIGINT"), (signal.SIGTERM, "SIGTERM")):
    code, summary, said = run("stop-" + name, sig)
    if code != -sig or summary["interrupted_by"] != name:
        sys.exit("FAIL: %s: status %d, interrupted_by %r" % (name, code, summary["interrupted_by"]))
    if not 1 <= summary["scans"] < total or "interrupted by " + name not in said:
        sys.exit("FAIL: %s: %d of %d scans; said %r" % (name, summary["scans"], total, said))
code, summary, _ = run("ignored", signal.SIGINT, ignore=True, every="0")
if code != 0 or summary["interrupted_by"] is not None or summary["scans"] != total:
    sys.exit("FAIL: an ignored SIGINT: status %d, %d of %d scans" % (code, summary["scans"], total))

# eval --seeds: SIGINT once the first drive is scored stops after the drive at hand; seeds.json
# holds the drives done, in order, and names the signal.
child = subprocess.Popen(
    [bin, "eval", "--seeds", "1-4", "--scenarios", "parking", "--duration", "5", "--out",
     out + "/eval-stop"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
first = child.stdout.readline()
if "parking seed 1:" not in first:
    sys.exit("FAIL: eval --seeds: first line %r" % first)
child.send_signal(signal.SIGINT)
_, said = child.communicate()
seeds = json.load(open(out + "/eval-stop/seeds.json"))
done = seeds["scenarios"][0]["seeds"]
if child.returncode != -signal.SIGINT or seeds["interrupted_by"] != "SIGINT":
    sys.exit("FAIL: eval --seeds: status %d, interrupted_by %r" % (child.returncode,
                                                                  seeds["interrupted_by"]))
if not 1 <= len(done) < 4 or done != list(range(1, len(done) + 1)) or \
        "after %d of 4 drives" % len(done) not in said:
    sys.exit("FAIL: eval --seeds: drives %r; said %r" % (done, said))

def start(args, **kw):
    return subprocess.Popen([bin] + args, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, preexec_fn=lambda: signal.signal(signal.SIGINT,
                                                                        signal.SIG_DFL), **kw)

def ended_by_sigint(child, what):
    _, said = child.communicate()
    if child.returncode != -signal.SIGINT:
        sys.exit("FAIL: %s: status %d; said %r" % (what, child.returncode, said[-300:]))
    return said

# eval --log: SIGINT once it says it is scoring; eval.json holds the scans scored.
child = start(["eval", "--log", out + "/long/sim.fslog", "--truth", out + "/long/truth.json",
               "--out", out + "/eval-log-stop"])
if "scoring" not in child.stderr.readline():
    sys.exit("FAIL: eval --log: no line before scoring")
child.send_signal(signal.SIGINT)
said = ended_by_sigint(child, "eval --log")
report = json.load(open(out + "/eval-log-stop/eval.json"))
if report["interrupted_by"] != "SIGINT" or not report["scans_read"] < total or \
        len(report["per_scan"]) != report["summary"]["scans"]:
    sys.exit("FAIL: eval --log: %r of %d scans" % (report["scans_read"], total))

# demo: SIGINT once polygons.jsonl holds a line. Its log, truth, polygons and eval.json agree on
# the scans done, demo.avi is a whole AVI (the RIFF size is the file's), and `eval` scores the
# drive as it was cut.
demo = out + "/demo-stop"
child = start(["demo", "--duration", "30", "--snapshot-every", "1", "--out", demo])
deadline = time.monotonic() + 60
while child.poll() is None and time.monotonic() < deadline and not (
        os.path.exists(demo + "/polygons.jsonl") and
        b"\n" in open(demo + "/polygons.jsonl", "rb").read()):
    time.sleep(0.005)
child.send_signal(signal.SIGINT)
said = ended_by_sigint(child, "demo")
planned = re.search(r"interrupted by SIGINT after \d+ of (\d+) scans", said)
if planned is None:
    sys.exit("FAIL: demo: does not say how far it got: %r" % said[-300:])
total = int(planned.group(1))
report = json.load(open(demo + "/eval.json"))
logged = sum(1 for line in open(demo + "/sim.fslog") if line.startswith("SCAN"))
lines = open(demo + "/polygons.jsonl").read().split("\n")
avi = open(demo + "/demo.avi", "rb").read()
if report["interrupted_by"] != "SIGINT" or not 1 <= logged < total or \
        report["summary"]["scans"] != logged or len(lines) - 1 != logged or lines[-1] != "":
    sys.exit("FAIL: demo: %d scans logged, eval.json %r" % (logged, report["summary"]["scans"]))
if avi[:4] != b"RIFF" or int.from_bytes(avi[4:8], "little") != len(avi) - 8:
    sys.exit("FAIL: demo: demo.avi is not a whole AVI file")
again = subprocess.run([bin, "eval", "--log", demo + "/sim.fslog", "--truth", demo +
                        "/truth.json", "--out", demo + "/again", "--quiet"])
if again.returncode != 0 or \
        json.load(open(demo + "/again/eval.json"))["summary"]["scans"] != logged:
    sys.exit("FAIL: demo: the cut drive does not score again")

# simulate: SIGINT once sim.fslog holds data; the log and the truth hold the same scans, whole,
# and `eval` scores them.
sim = out + "/simulate-stop"
child = start(["simulate", "--scenario", "urban", "--duration", "120", "--out", sim])
deadline = time.monotonic() + 60
while child.poll() is None and time.monotonic() < deadline and not (
        os.path.exists(sim + "/sim.fslog") and os.path.getsize(sim + "/sim.fslog") > 0):
    time.sleep(0.002)
child.send_signal(signal.SIGINT)
said = ended_by_sigint(child, "simulate")
logged = sum(1 for line in open(sim + "/sim.fslog") if line.startswith("SCAN"))
truth_scans = len(json.load(open(sim + "/truth.json"))["scans"])
if not 1 <= logged < 3001 or truth_scans != logged or \
        "after %d of 3001 cycles" % logged not in said:
    sys.exit("FAIL: simulate: %d scans logged, %d in the truth; said %r" % (logged, truth_scans,
                                                                          said[-300:]))
again = subprocess.run([bin, "eval", "--log", sim + "/sim.fslog", "--truth", sim + "/truth.json",
                        "--out", sim + "/eval", "--quiet"])
if again.returncode != 0 or json.load(open(sim + "/eval/eval.json"))["summary"]["scans"] != logged:
    sys.exit("FAIL: simulate: the cut drive does not score")

# demo --seeds: SIGINT once the first drive has written its eval.json; seeds.json holds the
# drives done.
child = start(["demo", "--seeds", "1-3", "--scenarios", "parking", "--duration", "5", "--out",
               out + "/demo-seeds-stop"])
deadline = time.monotonic() + 60
while child.poll() is None and time.monotonic() < deadline and \
        not os.path.exists(out + "/demo-seeds-stop/parking-1/eval.json"):
    time.sleep(0.005)
child.send_signal(signal.SIGINT)
ended_by_sigint(child, "demo --seeds")
seeds = json.load(open(out + "/demo-seeds-stop/seeds.json"))
done = seeds["scenarios"][0]["seeds"]
if seeds["interrupted_by"] != "SIGINT" or not 1 <= len(done) < 3:
    sys.exit("FAIL: demo --seeds: drives %r, interrupted_by %r" % (done, seeds["interrupted_by"]))
PY

# eval: scores every scan.
"$bin" eval --log "$out/sim/sim.fslog" --truth "$out/sim/truth.json" --out "$out/eval" \
  >"$out/eval.txt" 2>&1 || fail "eval failed: $(cat "$out/eval.txt")"
grep -q "cell accuracy" "$out/eval.txt" || fail "eval prints no accuracy"
grep -q '"per_scan"' "$out/eval/eval.json" || fail "eval.json has no per_scan"
[ "$(grep -c '"coverage_seen"' "$out/eval/eval.json")" -ge 26 ] || fail "eval.json per-scan"
grep -q '"malformed_lines": 0' "$out/eval/eval.json" || fail "eval.json malformed_lines"
# A malformed last line: warned about and counted, like any other.
{ cat "$out/sim/sim.fslog"; echo "SCAN 99.5 garbage"; } >"$out/bad-tail.fslog"
"$bin" eval --log "$out/bad-tail.fslog" --truth "$out/sim/truth.json" --out "$out/eval-tail" \
  >"$out/eval-tail.txt" 2>&1 || fail "eval with a malformed last line failed"
grep -q "bad-tail.fslog:$(wc -l <"$out/bad-tail.fslog"): " "$out/eval-tail.txt" \
  || fail "malformed last line not reported: $(cat "$out/eval-tail.txt")"
grep -q '"malformed_lines": 1' "$out/eval-tail/eval.json" || fail "malformed last line not counted"

# A truth of another drive: exit 2 and a message saying so.
"$bin" simulate --scenario parking --duration 0.5 --seed 5 --out "$out/short" 2>/dev/null
"$bin" eval --log "$out/sim/sim.fslog" --truth "$out/short/truth.json" --out "$out/bad" \
  >"$out/bad.txt" 2>&1
[ $? -eq 2 ] || fail "eval against a foreign truth must exit 2"
grep -q "does not belong" "$out/bad.txt" || fail "foreign truth not reported"
"$bin" eval --log "$out/sim/sim.fslog" --truth "$out/sim/sim.fslog" --out "$out/bad" \
  >/dev/null 2>&1
[ $? -eq 2 ] || fail "eval with a log as truth must exit 2"

# demo: every output.
"$bin" demo --scenario highway --duration 1 --snapshot-every 10 --out "$out/demo" --quiet \
  >"$out/demo.txt" 2>&1 || fail "demo failed: $(cat "$out/demo.txt")"
for f in sim.fslog sim.clf truth.json config.yaml polygons.jsonl eval.json demo.avi \
  snapshot_000000.png snapshot_000025.png; do
  [ -s "$out/demo/$f" ] || fail "demo wrote no $f"
done
grep -q "median ms per scan" "$out/demo.txt" || fail "demo prints no timings"
grep -q "polygon coverage" "$out/demo.txt" || fail "demo prints no quality"
head -c 4 "$out/demo/demo.avi" | grep -q RIFF || fail "demo.avi is not an AVI file"
# --video-max-mb: the video stops, said, before it passes the cap, and what it holds is a whole
# AVI file. 8 MiB holds some frames of a 3 s drive but not its 38 (about 80 kB each, and room
# kept for the next of twice the raw image).
"$bin" demo --scenario highway --duration 3 --snapshot-every 0 --video-max-mb 8 \
  --out "$out/demo-cap" --quiet >"$out/demo-cap.txt" 2>&1 ||
  fail "demo with --video-max-mb failed: $(cat "$out/demo-cap.txt")"
grep -q "demo.avi stops before scan [0-9]* at 8 MiB" "$out/demo-cap.txt" ||
  fail "demo does not say the video stopped: $(cat "$out/demo-cap.txt")"
frames=$(sed -n 's/.*demo.avi (\([0-9]*\) frames, stopped at --video-max-mb).*/\1/p' "$out/demo-cap.txt")
[ -n "$frames" ] && [ "$frames" -gt 1 ] && [ "$frames" -lt 38 ] ||
  fail "demo's summary does not say how many frames the stopped video holds: $(cat "$out/demo-cap.txt")"
[ "$(stat -c %s "$out/demo-cap/demo.avi")" -le $((8 << 20)) ] || fail "demo.avi passed its cap"
head -c 4 "$out/demo-cap/demo.avi" | grep -q RIFF || fail "the stopped demo.avi is not an AVI file"
# Without --config the demo runs the road setup of configs/scala.yaml: its sensor's sweep, its
# sensor model and polygon fields as that file has them (the demo writes numbers to 17 digits).
for field in "sweep_s: 0.016" "free_on_outline: false" "shape: inside" "max_vertices: 128" \
  "margin_cells: 1" "margin_cone_deg: 10" "face_tolerance_m: 0.05" "mover_memory_s: 3"; do
  grep -q "^  $field[0-9]*\$" "$out/demo/config.yaml" || fail "demo config lacks '$field'"
  grep -q "^  $field\$" "$src/configs/scala.yaml" || fail "configs/scala.yaml lacks '$field'"
done

# summary.json's polygon counts: a scan without a polygon (nothing free around the sensor yet, as
# at the first scan of this drive with the default config) is no_free_space, not a polygon that
# missed the vehicle.
"$bin" simulate --scenario parking --duration 2 --seed 3 --out "$out/p3" >/dev/null 2>&1 ||
  fail "simulate parking failed"
"$bin" run --log "$out/p3/sim.fslog" --out "$out/p3-run" --quiet 2>/dev/null ||
  fail "run of the parking drive failed"
/usr/bin/python3 - "$out/p3-run" <<'PY' || fail "summary.json's polygon counts"
import json, sys
summary = json.load(open(sys.argv[1] + "/summary.json"))["polygon"]
none = sum(json.loads(l)["polygon_status"] == "no_free_space" for l in open(sys.argv[1] + "/polygons.jsonl"))
if none < 1 or summary["no_free_space"] != none or summary["vehicle_outside"] != 0:
    sys.exit("%d scans without a polygon; summary %r" % (none, summary))
PY

# eval --seeds records the config its drives ran: with --rig surround, the rig's four sensors
# and its footprint (the config's polygon kept), and the config runs the drive's log again.
"$bin" eval --seeds 1 --scenarios parking --rig surround --duration 0.5 --quiet \
  --config "$src/configs/scala.yaml" --out "$out/eval-rig" >"$out/eval-rig.txt" 2>&1 ||
  fail "eval --rig surround failed: $(cat "$out/eval-rig.txt")"
/usr/bin/python3 - "$out" <<'PY' || fail "seeds.json's config is not the rig's"
import json, re, sys
config = json.load(open(sys.argv[1] + "/eval-rig/seeds.json"))["config"]
names = re.findall(r'^  - name: "(\w+)"$', config, re.M)
if names != ["front_left", "front_right", "rear_left", "rear_right"]:
    sys.exit("sensors %r in:\n%s" % (names, config))
for field in ("footprint_length_m: 4.7", "shape: inside", "margin_cells: 1"):
    if not re.search("^  " + field, config, re.M):
        sys.exit("no '%s' in:\n%s" % (field, config))
open(sys.argv[1] + "/eval-rig/config.yaml", "w").write(config)
PY
# demo --rig takes the road setup's config as eval --seeds does: the rig's own sensors, the
# config's other sections.
"$bin" demo --scenario parking --rig surround --duration 0.3 \
  --config "$src/configs/scala.yaml" --out "$out/demo-rig" >"$out/demo-rig.txt" 2>&1 ||
  fail "demo --rig surround --config scala.yaml failed: $(cat "$out/demo-rig.txt")"
[ "$(grep -c '^  - name: ' "$out/demo-rig/config.yaml")" -eq 4 ] ||
  fail "demo --rig surround's config.yaml has not the rig's four sensors"
grep -q '^  shape: inside' "$out/demo-rig/config.yaml" ||
  fail "demo --rig surround's config.yaml lost the config's polygon section"
"$bin" simulate --rig surround --scenario parking --seed 1 --duration 0.5 --out "$out/sim-rig" \
  >/dev/null 2>&1 || fail "simulate --rig surround failed"
"$bin" eval --log "$out/sim-rig/sim.fslog" --truth "$out/sim-rig/truth.json" --quiet \
  --config "$out/eval-rig/config.yaml" --out "$out/eval-rig-log" >"$out/eval-rig-log.txt" 2>&1 ||
  fail "seeds.json's config does not run the rig's log: $(cat "$out/eval-rig-log.txt")"

# A rig's log: the summary counts scans, a rig's cycles apart; a scanner that sends empty scans
# is warned about per cycle, counted under its name, and stops --strict; --max-scans counts
# scans. Sensor 2 (rear_left) of the 0.5 s drive sends empty scans.
awk '$1 == "SCAN" && $2 == 2 { print "SCAN 2", $3, $4, $5, $6, 0; next } { print }' \
  "$out/sim-rig/sim.fslog" >"$out/rig-dead.fslog"
"$bin" run --log "$out/rig-dead.fslog" --strict --quiet --out "$out/rig-dead-strict" \
  >"$out/rig-dead-strict.txt" 2>&1
[ $? -eq 1 ] || fail "--strict did not stop at a rig's empty scan"
grep -q "cycle 0: sensor 2 (rear_left): empty scan" "$out/rig-dead-strict.txt" ||
  fail "the empty scan's sensor is not named: $(cat "$out/rig-dead-strict.txt")"
"$bin" run --log "$out/rig-dead.fslog" --quiet --out "$out/rig-dead" >/dev/null 2>&1 ||
  fail "run on a rig's log with empty scans failed"
"$bin" run --log "$out/sim-rig/sim.fslog" --quiet --max-scans 6 --out "$out/rig-max" \
  >/dev/null 2>&1 || fail "run --max-scans on a rig's log failed"
# A cycle cut by --max-scans: its warning cites the lines of the scans read and says so.
"$bin" run --log "$out/rig-dead.fslog" --max-scans 7 --out "$out/rig-dead-cut" \
  >"$out/rig-dead-cut.txt" 2>&1 || fail "run --max-scans 7 on the rig's log failed"
line1=$(grep -n '^SCAN' "$out/rig-dead.fslog" | sed -n 5p | cut -d: -f1)
line3=$(grep -n '^SCAN' "$out/rig-dead.fslog" | sed -n 7p | cut -d: -f1)
grep -q "rig-dead.fslog:$line1-$line3: cycle 1: .*(--max-scans cut the cycle after 3 scans)" \
  "$out/rig-dead-cut.txt" || fail "the cut cycle's warning: $(cat "$out/rig-dead-cut.txt")"
/usr/bin/python3 - "$out" <<'PY' || fail "a rig's summary.json does not add up"
import json, sys
s = json.load(open(sys.argv[1] + "/rig-dead/summary.json"))
cycles = s["cycles"]
assert s["scans_read"] == 4 * cycles["read"] == s["scans"] + s["skipped"], s
assert s["no_sensor_update"] == cycles["processed"], s
rear = cycles["sensors"]["rear_left"]
assert rear == {"scans": cycles["processed"], "no_update": cycles["processed"], "missing": 0}, s
assert cycles["sensors"]["front_left"]["no_update"] == 0, s
m = json.load(open(sys.argv[1] + "/rig-max/summary.json"))
assert m["scans_read"] == m["scans"] == 6 and m["cycles"]["read"] == 2, m
# The second cycle, cut to 2 scans by --max-scans, misses no sensor.
assert all(s["missing"] == 0 for s in m["cycles"]["sensors"].values()), m
PY

# Bad arguments.
"$bin" demo --scenario moon --out "$out/x" >/dev/null 2>&1 && fail "unknown scenario accepted"
"$bin" simulate --odometry-noise huge --out "$out/x" >/dev/null 2>&1 && fail "bad noise accepted"

echo "sim cli: all cases passed"
