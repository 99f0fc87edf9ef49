#!/bin/bash
# Issue 12's placement figures on the shared scenes (../shared/scenes), written to
# out/bench-place/report.md and report.json:
#  1. counts: probes voting and grid need for 95 % and 99 % coverage, without a camera (what free space
#     sees) and with the walk's camera (what the walk sees; coverage feedback too), with seconds and
#     peak memory of `place`;
#  2. walks: at equal budgets, path / voting / grid / coverage probes baked (traced, CPU) and rendered
#     along the walk, compared with an Embree reference: MAE, worst frame, flicker, uncovered pixels;
#  3. every probe set checked by `info --probes` (Embree alone): probes inside geometry.
# Usage: bash tools/bench_place.sh [sibenik] [fzk-haus]
# Environment: CUBEAO_BIN (default build/cubeao, built if missing), CUBEAO_PLACE_BUDGETS ("12 24 48"),
# CUBEAO_PLACE_SIZE (walk image WxH, 160x90), CUBEAO_PLACE_SPP (reference rays per pixel, 256),
# CUBEAO_PLACE_RES (bake face size, 256), CUBEAO_PLACE_BAKE_SPP (rays per traced texel, 32),
# CUBEAO_PLACE_PARTS ("counts walks"), CUBEAO_PLACE_METHODS (walk methods, "path voting grid coverage"). References are traced once into out/place-walks/NAME/reference
# and reused while their size and rays match.
set -euo pipefail
cd "$(dirname "$0")/.."
source tools/walk_scenes.sh
bin=${CUBEAO_BIN:-build/cubeao}
if [ ! -x "$bin" ]; then
  bash tools/install-deps.sh
  bash tools/build.sh --target cubeao
fi
budgets=${CUBEAO_PLACE_BUDGETS:-12 24 48}
size=${CUBEAO_PLACE_SIZE:-160x90}
spp=${CUBEAO_PLACE_SPP:-256}
res=${CUBEAO_PLACE_RES:-256}
bake_spp=${CUBEAO_PLACE_BAKE_SPP:-32}
parts=${CUBEAO_PLACE_PARTS:-counts walks}
methods=${CUBEAO_PLACE_METHODS:-path voting grid coverage}
out=out/bench-place
mkdir -p "$out"
rows=$out/rows.jsonl
: >"$rows"

# place NAME SCENE ARGS...: runs `place`, checks the probes with `info --probes`, appends one JSON row.
place() {
  local name=$1 scene=$2
  shift 2
  local start end json
  start=$(date +%s%N)
  json=$("$bin" place "$scene" --res "$res" --out "$out/$name.json" --json "$@" | tail -1)
  end=$(date +%s%N)
  local check
  check=$("$bin" info "$scene" --probes "$out/$name.json" --json | tail -1)
  python3 - "$name" "$json" "$check" "$((end - start))" >>"$rows" <<'PY'
import json, sys
name, place, check, seconds = sys.argv[1], json.loads(sys.argv[2]), json.loads(sys.argv[3]), int(sys.argv[4]) * 1e-9
print(json.dumps({"name": name, "kind": "place", "place": place, "check": check["probe_check"], "seconds": seconds}))
PY
}

[ $# -gt 0 ] || set -- sibenik fzk-haus
for which in "$@"; do
  walk_scene "$which" bench_place.sh
  if [[ " $parts " == *" counts "* ]]; then
    for target in 0.95 0.99; do
      for m in voting grid; do
        echo "== $which: $m, coverage $target of what free space sees"
        place "$which-free-$m-$target" "$scene" --method "$m" --coverage-target "$target"
        echo "== $which: $m, coverage $target of what the walk sees"
        place "$which-walk-$m-$target" "$scene" --method "$m" --coverage-target "$target" --camera "$walk"
      done
      echo "== $which: coverage feedback, target $target per frame"
      place "$which-walk-coverage-$target" "$scene" --method coverage --coverage-target "$target" --camera "$walk"
    done
  fi
  if [[ " $parts " == *" walks "* ]]; then
    ref=out/place-walks/$which/reference
    if ! python3 tools/reference_matches.py "$ref" "$size" "$spp"; then
      echo "== $which: reference, $spp rays per pixel at $size"
      rm -rf "$ref"
      "$bin" reference "$scene" --camera "$walk" --width "${size%x*}" --height "${size#*x}" --spp "$spp" \
          --out "$ref" --json | tail -1 >/dev/null
    fi
    for budget in $budgets; do
      for m in $methods; do
        name=$which-$m-$budget
        echo "== $which: $m, $budget probes, bake and walk"
        # Equal budgets: voting and grid fill the budget (target 1); coverage feedback keeps its per-frame
        # target (0.95) and stops adding at the budget (target 1 would spend it all on the first frames).
        target=1
        [ "$m" = coverage ] && target=0.95
        place "$name" "$scene" --method "$m" --budget "$budget" --coverage-target "$target" --camera "$walk"
        "$bin" bake "$scene" --probes "$out/$name.json" --out "$out/$name.cubeao" --res "$res" --estimator traced \
            --spp "$bake_spp" --device cpu --json | tail -1 >"$out/$name-bake.json"
        rm -rf "$out/$name-render"
        "$bin" render "$scene" --camera "$walk" --width "${size%x*}" --height "${size#*x}" --method probes \
            --cache "$out/$name.cubeao" --out "$out/$name-render" --json | tail -1 >"$out/$name-render.json"
        "$bin" compare "$out/$name-render" "$ref" --json | tail -1 >"$out/$name-compare.json"
        python3 - "$name" "$which" "$m" "$budget" "$out" >>"$rows" <<'PY'
import json, sys
name, scene, method, budget, out = sys.argv[1:]
c = json.load(open(f"{out}/{name}-compare.json"))
r = json.load(open(f"{out}/{name}-render.json"))
print(json.dumps({"name": name, "kind": "walk", "scene": scene, "method": method, "budget": int(budget),
                  "mae": c["mae"], "worst_frame_mae": max(f["mae"] for f in c["frames"]), "flicker": c["flicker"],
                  "ssim": c["ssim"], "uncovered": r.get("uncovered_fraction")}))
PY
        rm -rf "$out/$name-render" "$out/$name.cubeao"
      done
    done
  fi
done

python3 - "$rows" "$out" <<'PY'
import json, sys
rows = [json.loads(l) for l in open(sys.argv[1])]
out = sys.argv[2]
json.dump(rows, open(f"{out}/report.json", "w"), indent=1)
lines = []
places = [r for r in rows if r["kind"] == "place"]
if places:
    lines += ["| run | probes | coverage | coverage2 | place s | peak MB | inside geometry |",
              "|---|---|---|---|---|---|---|"]
    for r in places:
        p = r["place"]
        lines.append(f"| {r['name']} | {p['probes']} | {p['coverage']:.4f} | {p['coverage2']:.4f} | "
                     f"{r['seconds']:.1f} | {p['peak_memory_mb']:.0f} | {r['check']['inside']} |")
walks = [r for r in rows if r["kind"] == "walk"]
if walks:
    lines += ["", "| scene | method | budget | MAE | worst frame | flicker | SSIM | uncovered |",
              "|---|---|---|---|---|---|---|---|"]
    for r in walks:
        lines.append(f"| {r['scene']} | {r['method']} | {r['budget']} | {r['mae']:.4f} | {r['worst_frame_mae']:.4f} | "
                     f"{r['flicker']:.4f} | {r['ssim']:.3f} | {100 * (r['uncovered'] or 0):.2f} % |")
open(f"{out}/report.md", "w").write("\n".join(lines) + "\n")
print("\n".join(lines))
PY
