#!/usr/bin/env bash
# Issue 31's equal-count figure on the demo scene (builtin:cloister at the demo's 128², its own walk):
# voting with exactly N probes against the walk's eyes evenly spread (`path`), N = 6, 12, 24, each
# baked traced (64 rays, CPU), rendered along the walk and compared with a 256-ray reference.
#   bash tools/bench_place_demo.sh        (Env: BIN, build/cubeao by default)
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${BIN:-build/cubeao}
scene=builtin:cloister
out=out/place-demo
mkdir -p "$out"
[ -f "$out/ref/done" ] || { "$bin" reference "$scene" --spp 256 --out "$out/ref" > /dev/null && touch "$out/ref/done"; }
for n in 6 12 24; do
    for method in voting path; do
        name=$method-$n
        "$bin" place "$scene" --camera "$scene" --method "$method" --budget "$n" --res 128 --out "$out/$name.json" \
            > /dev/null
        "$bin" bake "$scene" --probes "$out/$name.json" --res 128 --estimator traced --device cpu \
            --out "$out/$name.cubeao" > /dev/null 2>&1
        "$bin" render "$scene" --cache "$out/$name.cubeao" --out "$out/$name" > /dev/null 2>&1
        "$bin" compare "$out/$name" "$out/ref" --json | tail -1 > "$out/$name.compare.json"
    done
    python3 - "$out" "$n" <<'PY'
import json, sys
out, n = sys.argv[1], sys.argv[2]
v = json.load(open(f"{out}/voting-{n}.compare.json"))["mae"]
p = json.load(open(f"{out}/path-{n}.compare.json"))["mae"]
print(f"cloister 128², {n:>2} probes: voting MAE {v:.4f}, path {p:.4f}, voting / path {v / p:.3f}")
PY
done
