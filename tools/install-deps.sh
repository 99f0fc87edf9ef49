#!/bin/bash
# Installs the Debian 12 packages cubeao builds and runs with (DESIGN.md §3), skipping the apt run
# entirely when all are present. Used by tools/demo.sh and tools/test.sh; safe to run again.
set -euo pipefail

packages=(
  build-essential cmake pkg-config python3
  ccache                               # compiler cache: CI's builds reuse the session's objects (CMakeLists.txt)
  libegl-dev libgl-dev libopengl-dev libegl-mesa0 libgl1-mesa-dri   # headless GL on Mesa (llvmpipe)
  libglfw3-dev libimgui-dev xvfb xauth                              # viewer window, panel; tested under Xvfb
  libglm-dev libopenmesh-dev libassimp-dev assimp-testmodels
  libembree-dev libtbb-dev
  libcgal-dev                          # placement: exact inside test, distance to the surface
  libopenimageio-dev openimageio-tools   # OIIO's CMake config insists on its tools being installed
  libcli11-dev nlohmann-json3-dev libxxhash-dev libspdlog-dev libfmt-dev
  libgtest-dev libsquish-dev                                        # libsquish: BC5 cross-check in tests/cache/test_bc.cpp
  clang libclang-rt-14-dev                                          # libFuzzer targets (tests/fuzz, tools/fuzz.sh)
  chromium fonts-liberation                                         # headless check of `cubeao report`'s page (tests/cli/test_report.cpp)
  slurm-wlm munge                                                   # tools/slurm/, tested on a private localhost cluster (tests/slurm_test.sh)
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

sudo=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "install-deps: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  sudo="sudo"
fi
echo "install-deps: installing ${missing[*]}"
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "install-deps: done"
