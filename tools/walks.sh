#!/bin/bash
# Issue 6's quality figures on the shared walks (../shared/scenes): probes against the screen-space
# baselines, every frame of the walk, each compared with an Embree reference whose own noise is below
# 0.005. Runs tools/demo.sh per scene with the walk's camera; the reference, the expensive part, is
# traced once into out/walks/NAME/reference and reused while its size and rays match.
# Usage: bash tools/walks.sh [sibenik] [fzk-haus]
# Environment: CUBEAO_WALK_SIZE (image WxH, default 320x180), CUBEAO_WALK_SPP (reference rays per
# pixel, default 512), CUBEAO_WALK_PROBES (24), CUBEAO_WALK_RES (probe face size, 512, the bake's
# default), CUBEAO_WALK_BAKE_SPP (rays per traced texel, 64), and CUBEAO_BIN as in demo.sh. Traced
# probes bake on the CPU path and horizon-split ones on the GPU path: each the faster of the two on
# a machine without a GPU (llvmpipe). The bakes skip demo.sh's texel-by-texel check (the traced
# CPU bake is the Embree twin itself).
set -euo pipefail
cd "$(dirname "$0")/.."
source tools/walk_scenes.sh
size=${CUBEAO_WALK_SIZE:-320x180}
spp=${CUBEAO_WALK_SPP:-512}
if [ -z "${CUBEAO_BIN:-}" ]; then
  bash tools/install-deps.sh
  bash tools/build.sh --target cubeao
  export CUBEAO_BIN=build/cubeao
fi

[ $# -gt 0 ] || set -- sibenik fzk-haus
for which in "$@"; do
  walk_scene "$which" walks.sh
  out=out/walks/$which
  ref=$out/reference
  if ! python3 tools/reference_matches.py "$ref" "$size" "$spp"; then
    echo "== $which: reference, $spp rays per pixel at $size (the long step)"
    rm -rf "$ref"
    "$CUBEAO_BIN" reference "$scene" --camera "$walk" --width "${size%x*}" --height "${size#*x}" --spp "$spp" \
        --out "$ref" --json | tail -1 >/dev/null
  fi
  echo "== $which"
  CUBEAO_DEMO_SCENE=$scene CUBEAO_DEMO_CAMERA=$walk CUBEAO_DEMO_SIZE=$size CUBEAO_DEMO_OUT=$out/run \
  CUBEAO_DEMO_REFERENCE=$ref CUBEAO_DEMO_PROBES=${CUBEAO_WALK_PROBES:-24} CUBEAO_DEMO_PLACE=${CUBEAO_WALK_PLACE:-voting} CUBEAO_DEMO_RES=${CUBEAO_WALK_RES:-512} \
  CUBEAO_DEMO_BAKE_SPP=${CUBEAO_WALK_BAKE_SPP:-64} CUBEAO_DEMO_DEVICE_TRACED=cpu CUBEAO_DEMO_DEVICE_HSPLIT=gpu \
  CUBEAO_DEMO_VERIFY=0 \
      bash tools/demo.sh
done
