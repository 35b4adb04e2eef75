#!/usr/bin/env bash
# Builds freespace with AddressSanitizer and UndefinedBehaviorSanitizer into ./build-asan and
# runs the whole test suite there; any sanitizer report fails the test that caused it. Leaks
# inside PoCL and its LLVM are suppressed (scripts/lsan.supp names only their frames). The
# Python tests run the interpreter with the sanitizer's runtime preloaded and leak checking
# off (tests/CMakeLists.txt); the tests that measure memory (RSS) or build against the
# installed package are left out of sanitizer builds.
# Usage: scripts/sanitize.sh [ctest arguments, e.g. -R errors_cli or -E opencl]
# FREESPACE_SANITIZE_OPENCL=OFF builds without the OpenCL backend (the host tests only, as CI
# runs them); FREESPACE_JOBS sets the build and test parallelism (default: all cores).
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install-deps.sh
jobs=${FREESPACE_JOBS:-$(nproc)}
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DFREESPACE_BUILD_BENCH=OFF \
  -DFREESPACE_SANITIZE="address;undefined" \
  -DFREESPACE_WITH_OPENCL="${FREESPACE_SANITIZE_OPENCL:-ON}" \
  -DFREESPACE_WITH_PYTHON=ON -DFREESPACE_WITH_ROS=ON -DPython3_EXECUTABLE=/usr/bin/python3 >/dev/null
cmake --build build-asan -j"$jobs"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1"
export LSAN_OPTIONS="suppressions=$PWD/scripts/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
cd build-asan
ctest --output-on-failure -j"$jobs" "$@"
