#!/bin/bash
# Per-texel quality of every bake estimator against a many-ray Embree reference at the same texel
# points, before any blur (issue "probe bake": traced at 64 rays must reach MAE <= 0.03), on the
# real scenes of ../shared/scenes. Prints a Markdown table for docs/BENCHMARKS.md.
# Usage: tools/bench_bake_quality.sh [RES (128)] [REFERENCE_SPP (1024)] [PROBES (3)]
set -euo pipefail
cd "$(dirname "$0")/.."
res=${1:-128}
refspp=${2:-1024}
nprobes=${3:-3}
bin=build/cubeao
shared=../shared/scenes
out=out/bench/bake_quality
mkdir -p "$out"

scenes=("$shared/sibenik/sibenik.obj|$shared/sibenik/walk.json|sibenik"
        "/usr/share/assimp/models/IFC/AC14-FZK-Haus.ifc|$shared/fzk-haus/walk.json|fzk-haus")
echo "| scene | estimator | device | res | MAE vs ${refspp}-ray reference | reference noise | traced texels | ms/probe |"
echo "|---|---|---|---|---|---|---|---|"
for entry in "${scenes[@]}"; do
  IFS='|' read -r scene camera name <<<"$entry"
  [ -f "$scene" ] || { echo "skipping $name: $scene not found" >&2; continue; }
  "$bin" place "$scene" --method path --camera "$camera" --budget "$nprobes" --out "$out/$name-probes.json" >/dev/null
  for est in traced hsplit gtao hybrid; do
    "$bin" bake "$scene" --probes "$out/$name-probes.json" --out "$out/$name-$est" --res "$res" --spp 64 \
      --estimator "$est" --verify --verify-spp "$refspp" --json 2>/dev/null | tail -1 >"$out/$name-$est.json"
    python3 - "$out/$name-$est.json" "$name" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
s = j["settings"]
print(f"| {sys.argv[2]} | {s['estimator']} | {s['device']} | {s['res']} | {j['verify_mae']:.4f} | "
      f"{j['verify_noise']:.4f} | {100 * j['traced_fraction']:.1f} % | {j['ms_per_probe']:.0f} |")
PY
  done
done
