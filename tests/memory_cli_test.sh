#!/usr/bin/env bash
# `freespace simulate` and `freespace run` hold memory independent of the drive's length: the
# peak RSS (the kernel's ru_maxrss of each child) of a 30 s urban drive and of one four times
# as long (120 s: the scenario's 32 s, then standing while the traffic moves), simulated and
# then run, differ by less than 1.5 MB (each the least of two runs). (Keeping every scan's truth
# until the end, as simulate once did, cost about 2 kB a scan here: some 5 MB more for the long
# drive.)
# Usage: memory_cli_test.sh FREESPACE_BINARY SOURCE_DIR OUT_DIR
set -u
bin=$1 src=$2 out=$3
rm -rf "$out" && mkdir -p "$out"

python3 - "$bin" "$src" "$out" <<'PY'
import os, subprocess, sys

bin, src, out = sys.argv[1:4]

def peak_rss_kb(args):
    """Runs the command; its peak resident set (kB), or exits on failure."""
    with open(out + "/log.txt", "ab") as log:
        child = subprocess.Popen([bin] + args, stdout=log, stderr=log)
        _, status, usage = os.wait4(child.pid, 0)
    if status != 0:
        sys.exit("FAIL: %s: exit status %d (%s/log.txt)" % (" ".join(args), status, out))
    return usage.ru_maxrss

# Each peak is the least of two runs: the threads' allocations interleave differently from run
# to run (a few hundred kB either way, more beside other tests), a growth with the drive shows
# in both.
peaks = {}
for seconds in (30, 120):
    d = "%s/d%d" % (out, seconds)
    peaks["simulate", seconds] = min(peak_rss_kb(
        ["simulate", "--scenario", "urban", "--seed", "5", "--duration", str(seconds),
         "--out", d + "/sim"]) for _ in range(2))
    peaks["run", seconds] = min(peak_rss_kb(
        ["run", "--log", d + "/sim/sim.fslog", "--config", src + "/configs/scala.yaml",
         "--backend", "tbb", "--snapshot-every", "0", "--quiet", "--out", d + "/run"])
        for _ in range(2))
bad = []
for command in ("simulate", "run"):
    short, long = peaks[command, 30], peaks[command, 120]
    print("%s: peak RSS %d kB (30 s), %d kB (120 s): %+d kB" % (command, short, long, long - short))
    if long - short > 1536:
        bad.append(command)
if bad:
    sys.exit("FAIL: peak RSS grows with the drive: " + ", ".join(bad))
print("peak RSS independent of the drive's length")
PY
