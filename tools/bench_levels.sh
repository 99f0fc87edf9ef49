#!/bin/bash
# Issue 34's levels of detail on the Sibenik walk (docs/BENCHMARKS.md "Levels of detail on disk"):
# 12 probes at every 10th eye, the default traced bake at 512² (CPU) with every level (`--levels max`:
# 512² … 16²), then
#  1. the cache's bytes per full-resolution texel with its whole chain (`cubeao info`),
#  2. frames 0:24 at 160×90 with every probe held at each level (`render --level K`) against a
#     512-ray reference: MAE, flicker, GPU bytes: what each level costs the picture, the figures the
#     residency's choice of level per probe is to be built on;
#  3. the same frames all resident and under GPU budgets, from the cache with levels (the coarse tier)
#     and from its level 0 alone (`merge --levels 1`: no tier): MAE, flicker, slots, tier level.
# Usage: bash tools/bench_levels.sh [OUT_DIR]   (default out/bench-levels; the bake and the reference
# are kept there and reused by the next run). Environment: CUBEAO_BIN (default build/cubeao),
# CUBEAO_LEVEL_BUDGETS (MiB, default "21.55 19.02 17": issue 34's quarter and eighth, then tighter).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bin=${CUBEAO_BIN:-$root/build/cubeao}
budgets=${CUBEAO_LEVEL_BUDGETS:-21.55 19.02 17}
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

[ -f one.cubeao ] || "$bin" merge one.cubeao levels.cubeao --levels 1
budgeted=()
for c in levels one; do
  for b in 0 $budgets; do
    run=${c}_budget_$b
    args=()
    [ "$b" != 0 ] && args=(--gpu-budget-mb "$b")
    if "$bin" render "$scene" --cache $c.cubeao --camera "$walk" --frames 0:24 --width 160 --height 90 "${args[@]}" \
      --out $run --json > $run.out 2> $run.log; then
      tail -1 $run.out > $run.json
      "$bin" compare $run ref24 --json | tail -1 > $run.compare.json
      budgeted+=("$run")
    else
      echo "$run: $(grep -m1 -i error $run.log $run.out)"
    fi
  done
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

python3 - "${budgeted[@]}" <<'PY'
import json, sys
print(f"{'run':22s} {'MAE':>7s} {'flicker':>8s} {'slots':>5s} {'tier':>4s} {'loads':>5s} {'uncov':>7s} {'GPU MiB':>8s}")
for run in sys.argv[1:]:
    j = json.load(open(f"{run}.json"))
    r = j["residency"]
    c = json.load(open(f"{run}.compare.json"))
    print(f"{run:22s} {c['mae']:7.4f} {c['flicker']:8.4f} {r['slots']:5d} {r['coarse_level']:4d} {r['loads']:5d} "
          f"{j['uncovered_fraction']:7.4f} {r['gpu_bytes'] / 2**20:8.2f}")
PY
