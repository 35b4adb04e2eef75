#!/usr/bin/env bash
# Builds the libFuzzer targets of tests/fuzz with Clang, AddressSanitizer and
# UndefinedBehaviorSanitizer into ./build-fuzz, and runs each for SECONDS (default 20) on a
# corpus seeded from the recorded logs (tests/data), configs/, tests/fuzz/seeds/ and the
# inputs that once failed (tests/fuzz/regressions/). A crash, a sanitizer report or a broken
# contract (an exception escaping, an unprintable message) fails the script; the input that
# did it is left in build-fuzz/artifacts/ (keep it in tests/fuzz/regressions/<target>/ once
# fixed). Prints the runs each target made.
# Usage: scripts/fuzz.sh [SECONDS] [TARGET...]   (targets: native_log carmen_log kitti_log
#        config estimator)
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-20}
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(native_log carmen_log kitti_log config estimator)
command -v clang++ >/dev/null || { echo "fuzz: clang++ not found (scripts/install-deps.sh installs it)" >&2; exit 2; }
jobs=${FREESPACE_JOBS:-$(nproc)}
data=${FREESPACE_DATA_DIR:-tests/data}

cmake -S . -B build-fuzz -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DFREESPACE_FUZZ=ON -DFREESPACE_SANITIZE="address;undefined" -DFREESPACE_WITH_OPENCL=OFF \
  -DFREESPACE_BUILD_BENCH=OFF -DFREESPACE_WITH_PYTHON=OFF -DFREESPACE_WITH_ROS=OFF >/dev/null
cmake --build build-fuzz -j"$jobs" --target "${targets[@]/#/fuzz_}"

# The corpora: small pieces of the recorded logs and the shipped configs, plus the seeds and
# the regressions kept in the repository.
seed() {  # seed TARGET: fills build-fuzz/corpus/TARGET
  local dir=build-fuzz/corpus/$1
  mkdir -p "$dir"
  cp tests/fuzz/regressions/"$1"/* "$dir"/ 2>/dev/null || true
  cp tests/fuzz/seeds/"$1"/* "$dir"/ 2>/dev/null || true
  case $1 in
    carmen_log)
      for log in "$data"/carmen/intel-corrected.log "$data"/carmen/aces.clf "$data"/carmen/intel.clf; do
        [ -f "$log" ] || continue
        head -c 20000 "$log" >"$dir/$(basename "$log").head"
        tail -c 20000 "$log" | tail -n +2 >"$dir/$(basename "$log").tail"
      done ;;
    kitti_log)
      for bin in "$data"/kitti/*.bin; do
        [ -f "$bin" ] && head -c 32768 "$bin" >"$dir/$(basename "$bin").head"
      done ;;
    config) cp configs/*.yaml "$dir"/ ;;
  esac
}

export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
mkdir -p build-fuzz/artifacts
status=0
for target in "${targets[@]}"; do
  seed "$target"
  log=build-fuzz/fuzz_$target.log
  if build-fuzz/tests/fuzz/fuzz_"$target" build-fuzz/corpus/"$target" -max_total_time="$seconds" \
       -max_len=65536 -timeout=20 -rss_limit_mb=4096 -print_final_stats=1 \
       -artifact_prefix=build-fuzz/artifacts/"$target"- >"$log" 2>&1; then
    runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")
    echo "fuzz: $target: ${runs:-?} runs in $seconds s, nothing found"
  else
    echo "fuzz: $target FAILED (build-fuzz/artifacts/, log $log):"
    tail -n 30 "$log"
    status=1
  fi
done
exit $status
