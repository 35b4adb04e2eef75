#!/usr/bin/env bash
# `--save-map PREFIX` from the command line: `run` on a simulated drive and `demo` write a map
# that map_server loads (YAML with its seven keys, the image it names, a binary PGM of the map's
# size) and the raw log-odds as .npy (its header: int16, the map's shape).
# Usage: map_cli_test.sh FREESPACE_BINARY OUT_DIR
set -u
bin=$1 out=$2
rm -rf "$out" && mkdir -p "$out"
fail() { echo "FAIL: $*"; exit 1; }

"$bin" run --help | grep -q -- "--save-map" || fail "run --help does not document --save-map"
"$bin" simulate --scenario parking --duration 1 --seed 3 --out "$out/sim" 2>"$out/sim.err" \
  || fail "simulate failed: $(cat "$out/sim.err")"

# Checks PREFIX.yaml / .pgm / .npy of a W x H map at resolution RES.
check_map() {
  local prefix=$1 w=$2 h=$3 res=$4
  local yaml="$prefix.yaml"
  [ -s "$yaml" ] || fail "no $yaml"
  for key in image resolution origin negate occupied_thresh free_thresh mode; do
    grep -q "^$key: " "$yaml" || fail "$yaml has no key $key"
  done
  [ "$(grep -c '^[a-z_]*: ' "$yaml")" -eq 7 ] || fail "$yaml has keys besides map_server's"
  grep -qx "resolution: $res" "$yaml" || fail "$yaml resolution: $(grep resolution "$yaml")"
  grep -qx "mode: trinary" "$yaml" || fail "$yaml mode"
  grep -qx "negate: 0" "$yaml" || fail "$yaml negate"
  grep -qE '^origin: \[-?[0-9.e+-]+, -?[0-9.e+-]+, -?[0-9.e+-]+\]$' "$yaml" || fail "$yaml origin"
  local image
  image=$(sed -n 's/^image: "\(.*\)"$/\1/p' "$yaml")
  local pgm
  pgm="$(dirname "$yaml")/$image"
  [ -f "$pgm" ] || fail "$yaml names image $image, not found beside it"
  [ "$(head -c 2 "$pgm")" = "P5" ] || fail "$pgm is not a binary PGM"
  # Header: P5, a comment, "W H", 255; then W * H bytes.
  [ "$(sed -n 3p "$pgm")" = "$w $h" ] || fail "$pgm size line: $(sed -n 3p "$pgm")"
  [ "$(sed -n 4p "$pgm")" = "255" ] || fail "$pgm maxval: $(sed -n 4p "$pgm")"
  local header_bytes
  header_bytes=$(head -4 "$pgm" | wc -c)
  [ "$(stat -c %s "$pgm")" -eq $((header_bytes + w * h)) ] || fail "$pgm is not $w x $h bytes"
  # Every pixel is one of the trinary values, and the map has free and occupied cells.
  local counts
  counts=$(tail -c $((w * h)) "$pgm" | od -An -v -tu1 | tr -s ' ' '\n' | sed '/^$/d' | sort -n | uniq -c)
  echo "$counts" | awk '$2 != 0 && $2 != 205 && $2 != 254 { exit 1 }' \
    || fail "$pgm has values besides 0, 205, 254: $counts"
  echo "$counts" | grep -qE ' 254$' || fail "$pgm has no free pixel"
  echo "$counts" | grep -qE ' 0$' || fail "$pgm has no occupied pixel"
  local npy="$prefix.npy"
  [ "$(head -c 6 "$npy" | tail -c 5)" = "NUMPY" ] || fail "$npy magic"
  head -c 128 "$npy" | grep -aq "{'descr': '<i2', 'fortran_order': False, 'shape': ($h, $w), }" \
    || fail "$npy header: $(head -c 128 "$npy" | tail -c 118)"
  local npy_header=$(( $(od -An -j8 -N2 -tu2 "$npy") + 10 ))
  [ "$(stat -c %s "$npy")" -eq $((npy_header + 2 * w * h)) ] || fail "$npy is not $h x $w int16"
}

"$bin" run --log "$out/sim/sim.fslog" --out "$out/run" --quiet --save-map "$out/maps/run" \
  2>"$out/run.err" || fail "run --save-map failed: $(cat "$out/run.err")"
grep -q "wrote the map 300 x 300" "$out/run.err" || fail "run does not say it wrote the map"
check_map "$out/maps/run" 300 300 0.2

"$bin" demo --scenario parking --duration 1 --seed 3 --no-video --quiet --out "$out/demo" \
  --save-map "$out/demo/map" >"$out/demo.txt" 2>&1 || fail "demo --save-map: $(cat "$out/demo.txt")"
check_map "$out/demo/map" 300 300 0.2
# demo --seeds: each drive's map under its own prefix, none overwritten.
"$bin" demo --seeds 3-4 --scenario parking --duration 0.5 --quiet --out "$out/demo-seeds" \
  --save-map "$out/demo-seeds/map" >"$out/demo-seeds.txt" 2>&1 ||
  fail "demo --seeds --save-map: $(cat "$out/demo-seeds.txt")"
check_map "$out/demo-seeds/map-parking-3" 300 300 0.2
check_map "$out/demo-seeds/map-parking-4" 300 300 0.2
cmp -s "$out/demo-seeds/map-parking-3.npy" "$out/demo-seeds/map-parking-4.npy" &&
  fail "two drives' maps are the same file"

# An unwritable prefix: exit 2 with a message naming the file.
"$bin" run --log "$out/sim/sim.fslog" --out "$out/run2" --quiet --save-map /proc/no/such/map \
  >"$out/bad.txt" 2>&1
[ $? -eq 2 ] || fail "run --save-map into an unwritable folder must exit 2"
grep -q "/proc/no/such" "$out/bad.txt" || fail "unwritable map not named: $(cat "$out/bad.txt")"
echo "map files ok"
