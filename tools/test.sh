#!/bin/bash
# README command 2: install what is missing, build, run the whole test suite (GL tests on headless
# Mesa llvmpipe; they skip with the reason when no GL context can be made).
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-deps.sh
bash tools/build.sh
cd build
# The viewer's window test needs an X server; without one, run the suite under a virtual one (Xvfb).
if [ -z "${DISPLAY:-}" ] && command -v xvfb-run >/dev/null; then
  xvfb-run -a -s "-screen 0 640x480x24" ctest --output-on-failure -j2 --timeout 600
else
  ctest --output-on-failure -j2 --timeout 600
fi
