#!/usr/bin/env bash
# The project's test command: installs what is missing, builds, and runs the whole suite
# (GoogleTest cases and the command-line checks) with CTest.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/build.sh
cd build
ctest --output-on-failure -j"$(nproc)" "$@"
