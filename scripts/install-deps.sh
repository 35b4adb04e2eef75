#!/usr/bin/env bash
# Installs the Debian packages freespace needs to build, test and run, when any is missing.
# Runs apt-get (as root, or through sudo).
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libeigen3-dev libtbb-dev libopencv-dev libyaml-cpp-dev libcli11-dev nlohmann-json3-dev
  ocl-icd-opencl-dev opencl-headers opencl-clhpp-headers pocl-opencl-icd clinfo
  libgtest-dev libbenchmark-dev
  pybind11-dev python3-dev python3-numpy python3-yaml python3-dask python3-distributed
  python3-matplotlib
  # ROS 1 bags in and out (the optional freespace_ros target, ros/)
  librosbag-storage-dev libroscpp-core-dev libstd-msgs-dev libsensor-msgs-dev libnav-msgs-dev
  libgeometry-msgs-dev libtf2-msgs-dev
  clang libclang-rt-dev
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "install-deps: installing ${missing[*]}" >&2
sudo=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "install-deps: need root or sudo for apt-get" >&2; exit 1; }
  sudo="sudo"
fi
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
