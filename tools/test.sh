#!/bin/bash
# README command 2: install what is missing, build, run the whole test suite (GL tests on headless
# Mesa llvmpipe; they skip with the reason when no GL context can be made).
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-deps.sh
bash tools/build.sh
cd build
ctest --output-on-failure -j2 --timeout 600
