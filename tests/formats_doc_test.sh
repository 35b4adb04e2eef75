#!/usr/bin/env bash
# docs/formats.md against what the tools write: for polygons.jsonl, polygons.geojsonl,
# summary.json and eval.json, every key a file holds is documented in its example block, and
# every quoted name in the block is a key (or a string value) the file holds. Also the naming
# rule of docs/formats.md: a key whose number has a unit ends in the unit.
# Usage: formats_doc_test.sh FREESPACE_BINARY SOURCE_DIR OUT_DIR
set -u
bin=$1 src=$2 out=$3
rm -rf "$out" && mkdir -p "$out"
fail() { echo "FAIL: $*"; exit 1; }

"$bin" simulate --scenario parking --duration 2 --seed 2 --out "$out/sim" 2>"$out/sim.err" \
  || fail "simulate: $(cat "$out/sim.err")"
"$bin" run --log "$out/sim/sim.fslog" --out "$out/run" --quiet 2>"$out/run.err" \
  || fail "run: $(cat "$out/run.err")"
"$bin" run --log "$out/sim/sim.fslog" --out "$out/geo" --quiet --polygon-format geojson \
  2>"$out/geo.err" || fail "run --polygon-format geojson: $(cat "$out/geo.err")"
[ ! -e "$out/geo/polygons.jsonl" ] || fail "--polygon-format geojson also wrote polygons.jsonl"
"$bin" eval --log "$out/sim/sim.fslog" --truth "$out/sim/truth.json" --out "$out/eval" \
  >"$out/eval.txt" 2>&1 || fail "eval: $(cat "$out/eval.txt")"

python3 - "$src/docs/formats.md" "$out" <<'PY' || fail "docs/formats.md and the outputs differ"
import json, re, sys

doc = open(sys.argv[1]).read().split("\n")
out = sys.argv[2]
files = {
    "polygons.jsonl": (out + "/run/polygons.jsonl", True),
    "polygons.geojsonl": (out + "/geo/polygons.geojsonl", True),
    "summary.json": (out + "/run/summary.json", False),
    "eval.json": (out + "/eval/eval.json", False),
}

def block_after(name):
    """The first fenced block after the bullet that introduces `DIR/name`."""
    for i, line in enumerate(doc):
        if line.lstrip().startswith("- `DIR/" + name + "`"):
            start = next(j for j in range(i, len(doc)) if doc[j].strip().startswith("```"))
            end = next(j for j in range(start + 1, len(doc)) if doc[j].strip().startswith("```"))
            return "\n".join(doc[start + 1:end])
    sys.exit("formats.md documents no `DIR/%s`" % name)

def walk(v, keys, values):
    if isinstance(v, dict):
        for k, x in v.items():
            keys.add(k)
            walk(x, keys, values)
    elif isinstance(v, list):
        for x in v:
            walk(x, keys, values)
    elif isinstance(v, str):
        values.add(v)

# Units a key may end in, and keys that hold a number with a unit under another name.
units = ("_s", "_us", "_m", "_m2", "_mps", "_rad", "_deg", "_cells")
bad = []
for name, (path, lines) in files.items():
    text = open(path).read()
    json_objects = [json.loads(l) for l in text.splitlines()] if lines else [json.loads(text)]
    keys, values = set(), set()
    for o in json_objects:
        walk(o, keys, values)
    if not keys:
        sys.exit(name + ": nothing written")
    documented = set(re.findall(r'"([A-Za-z_][A-Za-z0-9_]*)"', block_after(name)))
    undocumented = sorted(keys - documented)
    unwritten = sorted(documented - keys - values)
    if undocumented:
        bad.append("%s writes keys formats.md does not show: %s" % (name, undocumented))
    if unwritten:
        bad.append("%s: formats.md shows names the file does not hold: %s" % (name, unwritten))
    for k in ("t", "time", "speed", "wall", "area", "intrusion", "range", "angle"):
        if k in keys:
            bad.append("%s: key %r has a unit but no unit suffix %s" % (name, k, units))
    print("%s: %d keys" % (name, len(keys)))
if bad:
    sys.exit("\n".join(bad))
PY
echo "formats.md matches the outputs"
