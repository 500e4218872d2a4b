#!/usr/bin/env bash
# Installs the Debian packages canopy needs to build and test. Idempotent: does nothing when
# everything is present. Needs root or sudo when something is missing.
set -euo pipefail

PACKAGES=(
  build-essential cmake ninja-build ccache pkg-config lld
  libmujoco-dev libqhull-dev libosmesa6-dev
  libeigen3-dev liboctomap-dev libompl-dev libfcl-dev liburdfdom-dev
  libboost-serialization-dev libboost-filesystem-dev libboost-system-dev
  libyaml-cpp-dev libcli11-dev libspdlog-dev libfmt-dev nlohmann-json3-dev
  libnanoflann-dev libtbb-dev libpng-dev libassimp-dev libssl-dev libstb-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  liblz4-dev libzstd-dev zlib1g-dev
  ffmpeg
  python3-yaml
  pybind11-dev python3-dev python3-numpy python3-pytest
  python3-rosbag python3-sensor-msgs python3-geometry-msgs python3-tf2-msgs python3-visualization-msgs
  python3-pil
  python3-xgboost libxgboost-dev python3-sklearn
  slurm-wlm munge parallel
  libjs-three
  chromium
)

# Node and npm run Foxglove's MCAP libraries, the reference the ros2 tests check canopy's
# recordings against (tests/ros2/reference). A Node that brings its own npm (NodeSource's nodejs
# provides and conflicts with Debian's npm package) is taken as it is.
if ! command -v node >/dev/null || ! command -v npm >/dev/null; then
  PACKAGES+=(nodejs npm)
fi

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]} == 0)); then
  exit 0
fi

echo "canopy: installing missing Debian packages: ${missing[*]}"
SUDO=""
if [[ $(id -u) -ne 0 ]]; then
  command -v sudo >/dev/null || { echo "canopy: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  SUDO=sudo
fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
