#!/usr/bin/env bash
# Configures and builds freespace (Release) in ./build, installing Debian packages first when
# any is missing.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)"
