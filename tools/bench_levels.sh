#!/bin/bash
# Issue 34's levels of detail on the Sibenik walk (docs/BENCHMARKS.md "Levels of detail on disk"):
# 12 probes at every 10th eye, the default traced bake at 512² (CPU) with every level (`--levels max`:
# 512² … 16²), then
#  1. the cache's bytes per full-resolution texel with its whole chain (`cubeao info`),
#  2. frames 0:24 at 160×90 with every probe held at each level (`render --level K`) against a
#     512-ray reference: MAE, flicker, GPU bytes: what each level costs the picture, the figures the
#     residency's choice of level per probe is to be built on.
# Usage: bash tools/bench_levels.sh [OUT_DIR]   (default out/bench-levels; the bake and the reference
# are kept there and reused by the next run). Environment: CUBEAO_BIN (default build/cubeao).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bin=${CUBEAO_BIN:-$root/build/cubeao}
out=${1:-$root/out/bench-levels}
scene=$root/../shared/scenes/sibenik/sibenik.obj
walk=$root/../shared/scenes/sibenik/walk.json
[ -f "$scene" ] || { echo "bench_levels: $scene not found (../shared/scenes)" >&2; exit 1; }
mkdir -p "$out"
cd "$out"

python3 - "$walk" probes.json <<'PY'
import json, sys
p = json.load(open(sys.argv[1]))
json.dump({"version": 1, "probes": [{"pos": f["eye"]} for f in p["frames"][::10]]}, open(sys.argv[2], "w"))
PY
[ -f levels.cubeao ] || "$bin" bake "$scene" --probes probes.json --out levels.cubeao --levels max --device cpu
"$bin" info levels.cubeao --json | tail -1 > levels.info.json
"$bin" info levels.cubeao

[ -d ref24 ] || "$bin" reference "$scene" --camera "$walk" --frames 0:24 --width 160 --height 90 --spp 512 \
  --out ref24 --json | tail -1 > ref24.json
levels=$(python3 -c 'import json; print(json.load(open("levels.info.json"))["levels"])')
rows=()
for ((k = 0; k < levels; k++)); do
  run=level_$k
  "$bin" render "$scene" --cache levels.cubeao --camera "$walk" --frames 0:24 --width 160 --height 90 --level $k \
    --out $run --json | tail -1 > $run.json
  "$bin" compare $run ref24 --json | tail -1 > $run.compare.json
  rows+=("$run")
done

python3 - "${rows[@]}" <<'PY'
import json, sys
info = json.load(open("levels.info.json"))
print(f"cache: {info['file_bytes']} bytes, {info['bytes_per_texel']:.4f} bytes per full-resolution texel, "
      f"{info['levels']} levels, {info['ao_format']}")
print(f"{'run':10s} {'faces':>6s} {'MAE':>7s} {'flicker':>8s} {'uncov':>7s} {'GPU MiB':>8s}")
for k, run in enumerate(sys.argv[1:]):
    r = json.load(open(f"{run}.json"))
    c = json.load(open(f"{run}.compare.json"))
    res = info["res"] >> k
    print(f"{run:10s} {res:5d}² {c['mae']:7.4f} {c['flicker']:8.4f} {r['uncovered_fraction']:7.4f} "
          f"{r['residency']['gpu_bytes'] / 2**20:8.2f}")
PY
