#!/bin/bash
# Issue 34's cache bytes and budgets on the Sibenik walk (docs/BENCHMARKS.md "Half the bytes per
# probe"): 12 probes at every 10th eye, the default traced bake at 512² (CPU) stored as BC5 (what
# earlier builds wrote) and converted to BC4 (what a traced bake writes now); then
#  1. both caches' sizes (`cubeao info`),
#  2. the whole walk rendered from each at 320×180, compared with each other (expected: identical),
#  3. frames 0:24 at 160×90 from each, all resident and under the issue's two budgets, against a
#     512-ray reference: MAE, flicker, slots, loads, GPU bytes.
# Usage: bash tools/bench_bc4.sh [OUT_DIR]   (default out/bench-bc4; the bake and the reference are
# kept there and reused by the next run). Environment: CUBEAO_BIN (default build/cubeao),
# CUBEAO_BC4_BUDGETS (MiB, "21.55 19.02": 16.5 MiB of the pass's own before staging was sized by the
# pool, plus a quarter / an eighth of the 12 probes' BC5 bytes).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bin=${CUBEAO_BIN:-$root/build/cubeao}
out=${1:-$root/out/bench-bc4}
budgets=${CUBEAO_BC4_BUDGETS:-21.55 19.02}
scene=$root/../shared/scenes/sibenik/sibenik.obj
walk=$root/../shared/scenes/sibenik/walk.json
[ -f "$scene" ] || { echo "bench_bc4: $scene not found (../shared/scenes)" >&2; exit 1; }
mkdir -p "$out"
cd "$out"

python3 - "$walk" probes.json <<'PY'
import json, sys
p = json.load(open(sys.argv[1]))
json.dump({"version": 1, "probes": [{"pos": f["eye"]} for f in p["frames"][::10]]}, open(sys.argv[2], "w"))
PY
[ -f bc5.cubeao ] || "$bin" bake "$scene" --probes probes.json --out bc5.cubeao --ao bc5 --device cpu
"$bin" merge bc4.cubeao bc5.cubeao --ao bc4
"$bin" info bc5.cubeao
"$bin" info bc4.cubeao

for f in bc5 bc4; do
  "$bin" render "$scene" --cache $f.cubeao --camera "$walk" --width 320 --height 180 --out walk_$f --json \
    | tail -1 > walk_$f.json
done
"$bin" compare walk_bc5 walk_bc4 --json | tail -1 > walk_bc5_vs_bc4.json

[ -d ref24 ] || "$bin" reference "$scene" --camera "$walk" --frames 0:24 --width 160 --height 90 --spp 512 \
  --out ref24 --json | tail -1 > ref24.json
rows=()
for f in bc5 bc4; do
  for b in 0 $budgets; do
    run=${f}_budget_$b
    args=()
    [ "$b" != 0 ] && args=(--gpu-budget-mb "$b")
    "$bin" render "$scene" --cache $f.cubeao --camera "$walk" --frames 0:24 --width 160 --height 90 "${args[@]}" \
      --out $run --json | tail -1 > $run.json
    "$bin" compare $run ref24 --json | tail -1 > $run.compare.json
    rows+=("$run")
  done
done

python3 - "${rows[@]}" <<'PY'
import json, sys
same = json.load(open("walk_bc5_vs_bc4.json"))
print(f"walk 320x180, BC5 against BC4: MAE {same['mae']:.6f}, SSIM {same['ssim']:.6f}")
print(f"{'run':22s} {'MAE':>7s} {'flicker':>8s} {'slots':>5s} {'loads':>5s} {'evict':>5s} {'GPU MiB':>8s} {'bound MiB':>9s}")
for run in sys.argv[1:]:
    r = json.load(open(f"{run}.json"))["residency"]
    c = json.load(open(f"{run}.compare.json"))
    print(f"{run:22s} {c['mae']:7.4f} {c['flicker']:8.4f} {r['slots']:5d} {r['loads']:5d} {r['evictions']:5d} "
          f"{r['gpu_bytes'] / 2**20:8.2f} {r['upload_bound_bytes'] / 2**20:9.2f}")
PY
