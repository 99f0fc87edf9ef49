#!/bin/bash
# MAE and flicker of the probes and of gtao on both shared walks (issue 13, docs/BENCHMARKS.md
# "Current figures"), at every blur width asked for: every frame of each walk at 160x90 against a
# 256-ray Embree reference (made once into out/place-walks/WALK/reference when missing: ~5 min for
# Sibenik, ~1 min for FZK-Haus on 2 cores).
# Usage: bash tools/bench_flicker.sh SIBENIK_CACHE FZK_CACHE [PROBE_TAPS [GTAO_TAPS]]
#   CUBEAO_FLICKER_SPP=1024: references of that many rays instead (out/place-walks/WALK/reference-sppN;
#   the reference's own noise is part of every flicker figure: BENCHMARKS "The bake's AO filter").
#   caches: 512² probes of each walk, e.g. `cubeao place SCENE --camera WALK --method voting
#   --coverage-target 1 --out P` then `cubeao bake SCENE --probes P --res 512 --spp 64 --estimator
#   traced --device cpu --out C` (about 50 s a probe here); taps: space-separated lists, default
#   "0 1 2 3" and "1 2 3". Writes out/bench-flicker/{WALK-METHOD-bN/, report.md}.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -lt 2 ]; then
  sed -n '2,12p' "$0" >&2
  exit 2
fi
bin=${CUBEAO_BIN:-build/cubeao}
shared=${CUBEAO_SHARED_DIR:-../shared}
probe_taps=${3:-0 1 2 3}
ref_spp=${CUBEAO_FLICKER_SPP:-256}
gtao_taps=${4:-1 2 3}
out=out/bench-flicker
mkdir -p "$out"
report=$out/report.md
echo "| walk | method | blur | MAE | flicker |" >"$report"
echo "|---|---|---|---|---|" >>"$report"

walk() {  # NAME SCENE CAMERA CACHE
  local name=$1 scene=$2 camera=$3 cache=$4 ref=out/place-walks/$1/reference
  [ "$ref_spp" = 256 ] || ref=$ref-spp$ref_spp
  [ -f "$cache" ] || { echo "bench_flicker: no cache $cache" >&2; exit 1; }
  if [ ! -f "$ref/reference.json" ]; then
    echo "== $name: reference ($ref_spp rays, 160x90)"
    "$bin" reference "$scene" --camera "$camera" --width 160 --height 90 --spp "$ref_spp" \
        --radius "$("$bin" info --json "$cache" | tail -1 | python3 -c 'import json,sys; print(json.load(sys.stdin)["radius"])')" \
        --out "$ref" >/dev/null
  fi
  local method taps b dir figures
  for method in probes gtao; do
    taps=$probe_taps
    [ "$method" = gtao ] && taps=$gtao_taps
    for b in $taps; do
      dir=$out/$name-$method-b$b
      rm -rf "$dir"
      "$bin" render "$scene" --camera "$camera" --width 160 --height 90 --method "$method" \
          $([ "$method" = probes ] && echo "--cache $cache") --blur "$b" --out "$dir" >/dev/null 2>&1
      figures=$("$bin" compare "$dir" "$ref" --json | tail -1 |
          python3 -c 'import json,sys; j=json.load(sys.stdin); print("%.4f | %.4f" % (j["mae"], j["flicker"]))')
      echo "| $name | $method | $b | $figures |" | tee -a "$report"
    done
  done
}

walk sibenik "$shared/scenes/sibenik/sibenik.obj" "$shared/scenes/sibenik/walk.json" "$1"
walk fzk-haus /usr/share/assimp/models/IFC/AC14-FZK-Haus.ifc "$shared/scenes/fzk-haus/walk.json" "$2"
echo "report: $report"
