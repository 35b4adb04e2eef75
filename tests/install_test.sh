#!/usr/bin/env bash
# The installed package as a user meets it: `cmake --install` into a temporary prefix, then
# examples/consumer configured with find_package(freespace) against that prefix only, built and
# run; the installed `freespace --version`, version header and LICENSE.
# Usage: install_test.sh CMAKE BUILD_DIR SOURCE_DIR OUT_DIR VERSION
set -u
cmake=$1 build=$2 src=$3 out=$4 version=$5
rm -rf "$out" && mkdir -p "$out"
fail() { echo "FAIL: $*"; exit 1; }
prefix="$out/prefix"

"$cmake" --install "$build" --prefix "$prefix" >"$out/install.log" 2>&1 \
  || fail "cmake --install failed: $(tail -20 "$out/install.log")"
[ -f "$prefix/include/freespace/freespace.hpp" ] || fail "no installed freespace.hpp"
grep -q "FREESPACE_VERSION_STRING \"$version\"" "$prefix/include/freespace/version.hpp" \
  || fail "installed version.hpp does not say $version"
grep -q "Apache License" "$prefix/share/doc/freespace/LICENSE" || fail "no installed LICENSE"
config="$prefix/lib/cmake/freespace/freespaceConfig.cmake"
[ -f "$config" ] || config=$(find "$prefix" -name freespaceConfig.cmake | head -1)
[ -f "$config" ] || fail "no installed freespaceConfig.cmake"
# Internal headers stay inside: nothing but include/freespace is installed.
[ "$(ls "$prefix/include")" = "freespace" ] || fail "installed include/ holds $(ls "$prefix/include")"

v=$("$prefix/bin/freespace" --version) || fail "installed freespace --version failed"
[ "$v" = "freespace $version" ] || fail "freespace --version says '$v', expected 'freespace $version'"

# The consumer sees only the prefix (no package registry, no other prefix).
"$cmake" -S "$src/examples/consumer" -B "$out/consumer" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF \
  -Dfreespace_DIR="$(dirname "$config")" >"$out/configure.log" 2>&1 \
  || fail "consumer configure failed: $(cat "$out/configure.log")"
"$cmake" --build "$out/consumer" -j2 >"$out/build.log" 2>&1 \
  || fail "consumer build failed: $(tail -40 "$out/build.log")"
"$out/consumer/consumer" >"$out/consumer.out" 2>"$out/consumer.err" \
  || fail "consumer failed: $(cat "$out/consumer.out" "$out/consumer.err")"
head -1 "$out/consumer.out" | grep -q "^freespace $version (headers $version), backend tbb$" \
  || fail "consumer's first line: $(head -1 "$out/consumer.out")"
[ "$(grep -c '^scan ' "$out/consumer.out")" -eq 25 ] || fail "consumer did not process 25 scans"
tail -2 "$out/consumer.out" | head -1 | grep -q "^scan 24: ok, [0-9]* vertices$" \
  || fail "last scan: $(tail -2 "$out/consumer.out" | head -1)"
grep -q "^map 300 x 300 at 0.2 m$" "$out/consumer.out" || fail "map line: $(tail -1 "$out/consumer.out")"

# The engine alone does not need OpenCV: the consumer configures with OpenCV out of reach.
"$cmake" -S "$src/examples/consumer" -B "$out/consumer-no-opencv" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF \
  -DCMAKE_DISABLE_FIND_PACKAGE_OpenCV=ON -Dfreespace_DIR="$(dirname "$config")" \
  >"$out/configure-no-opencv.log" 2>&1 ||
  fail "find_package(freespace) without OpenCV failed: $(tail -20 "$out/configure-no-opencv.log")"

# The baselines library under the name the docs and its own messages give (freespace::baselines),
# from a consumer that asks for C++14: the package's targets bring the C++17 its headers need
# (warnings as errors: C++14 only warns about inline variables).
mkdir -p "$out/baselines-src"
cat >"$out/baselines-src/CMakeLists.txt" <<'CMAKE'
cmake_minimum_required(VERSION 3.20)
project(baselines_consumer LANGUAGES CXX)
find_package(freespace REQUIRED COMPONENTS baselines)
add_executable(baselines_consumer main.cpp)
target_link_libraries(baselines_consumer PRIVATE freespace::baselines)
CMAKE
cat >"$out/baselines-src/main.cpp" <<'CPP'
#include <freespace/baselines.hpp>
int main() { freespace::RegisterBaselines(); }
CPP
"$cmake" -S "$out/baselines-src" -B "$out/baselines" -DCMAKE_PREFIX_PATH="$prefix" \
  -DCMAKE_CXX_STANDARD=14 -DCMAKE_CXX_FLAGS=-Werror -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF -Dfreespace_DIR="$(dirname "$config")" \
  >"$out/baselines.log" 2>&1 || fail "freespace::baselines not found: $(tail -20 "$out/baselines.log")"
"$cmake" --build "$out/baselines" >>"$out/baselines.log" 2>&1 &&
  "$out/baselines/baselines_consumer" || fail "freespace::baselines consumer: $(tail -20 "$out/baselines.log")"
# Asked for without OpenCV, the component fails to configure and says why.
"$cmake" -S "$out/baselines-src" -B "$out/baselines-no-opencv" -DCMAKE_PREFIX_PATH="$prefix" \
  -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF -DCMAKE_DISABLE_FIND_PACKAGE_OpenCV=ON \
  -Dfreespace_DIR="$(dirname "$config")" >"$out/baselines-no-opencv.log" 2>&1 &&
  fail "find_package(freespace COMPONENTS baselines) without OpenCV configured"
grep -q "the component baselines (freespace::baselines) needs OpenCV" \
  "$out/baselines-no-opencv.log" ||
  fail "no reason for the missing component: $(tail -20 "$out/baselines-no-opencv.log")"
# A component the package does not have is refused, naming the ones it has.
sed -i 's/COMPONENTS baselines/COMPONENTS baseline/' "$out/baselines-src/CMakeLists.txt"
"$cmake" -S "$out/baselines-src" -B "$out/baselines-misspelt" -DCMAKE_PREFIX_PATH="$prefix" \
  -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF -Dfreespace_DIR="$(dirname "$config")" \
  >"$out/baselines-misspelt.log" 2>&1 && fail "find_package(freespace COMPONENTS baseline) configured"
grep -q "no component 'baseline': the components are freespace and baselines" \
  "$out/baselines-misspelt.log" ||
  fail "no reason for the unknown component: $(tail -20 "$out/baselines-misspelt.log")"
echo "install + consumer ok: $(tail -2 "$out/consumer.out" | head -1)"
