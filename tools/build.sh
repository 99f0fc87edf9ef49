#!/bin/bash
# Configures and builds cubeao in build/ (Release). Extra arguments are passed to the build step,
# e.g. `tools/build.sh --target cubeao`. Two parallel jobs: CGAL/OIIO units are large on 2-core machines.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DCUBEAO_BUILD_TESTS=ON -DCUBEAO_BUILD_VIEWER=ON >/dev/null
cmake --build build -j2 "$@"
