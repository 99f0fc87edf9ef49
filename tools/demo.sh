#!/bin/bash
# README command 1: the main job end to end on a built-in scene (default builtin:cloister).
# Installs what is missing, builds, and runs what exists of the pipeline today:
#   info → reference AO of the scene's camera path (Embree, the ground truth) → a fast low-sample
#   reference → compare the two (what sampling noise alone costs in MAE/SSIM/flicker) → report.
# Later stages (place → bake → render) join this same command as they land.
# Environment: CUBEAO_DEMO_SCENE (default builtin:cloister), CUBEAO_DEMO_OUT (default out/demo),
# CUBEAO_DEMO_SPP (reference rays per pixel, default 128).
set -euo pipefail
cd "$(dirname "$0")/.."
scene=${CUBEAO_DEMO_SCENE:-builtin:cloister}
out=${CUBEAO_DEMO_OUT:-out/demo}
spp=${CUBEAO_DEMO_SPP:-128}

bash tools/install-deps.sh
bash tools/build.sh --target cubeao
bin=build/cubeao

rm -rf "$out"
mkdir -p "$out"
echo "== scene"
"$bin" info "$scene" --json | tee "$out/info.log" | tail -1 >"$out/info.json"
sed '$d' "$out/info.log"
echo "== reference: $spp rays per pixel"
"$bin" reference "$scene" --spp "$spp" --out "$out/reference" --json | tail -1 >"$out/reference.json"
echo "== fast reference: 8 rays per pixel"
"$bin" reference "$scene" --spp 8 --seed 1 --out "$out/reference-8spp" --json | tail -1 >"$out/reference-8spp.json"
echo "== compare 8 spp against $spp spp"
"$bin" compare "$out/reference-8spp" "$out/reference" --json | tee "$out/compare.log" | tail -1 >"$out/compare.json"

# A picture: first, middle and last frame, 8 spp (left) next to the reference (right).
frames=($(ls "$out/reference" | grep -E '^ao_[0-9]+\.png$' | sort))
pick=("${frames[0]}" "${frames[$(( ${#frames[@]} / 2 ))]}" "${frames[-1]}")
args=()
for f in "${pick[@]}"; do args+=("$out/reference-8spp/$f" "$out/reference/$f"); done
oiiotool "${args[@]}" --mosaic:pad=6 "2x${#pick[@]}" -o "$out/side_by_side.png"

python3 - "$out" <<'PY'
import json, sys, os
out = sys.argv[1]
load = lambda n: json.load(open(os.path.join(out, n)))
info, ref, fast, cmp = load("info.json"), load("reference.json"), load("reference-8spp.json"), load("compare.json")
report = {"scene": info, "reference": ref, "reference_8spp": fast, "compare_8spp_vs_reference": cmp,
          "images": {"side_by_side": os.path.join(out, "side_by_side.png"),
                     "reference": ref["out"], "reference_8spp": fast["out"]}}
json.dump(report, open(os.path.join(out, "report.json"), "w"), indent=1)
print()
print(f"scene      {info['scene']}: {info['triangles']} triangles, AO radius {ref['radius']:.3f}")
print(f"reference  {len(ref['frames'])} frames {ref['width']}x{ref['height']}, {ref['spp']} spp, "
      f"{ref['rays_per_s']/1e6:.1f} Mrays/s, noise (mean std. error) {ref['noise']:.4f}")
print()
print(f"{'method':<22}{'MAE':>8}{'RMSE':>8}{'SSIM':>8}{'flicker':>9}   (against the {ref['spp']}-spp reference)")
print(f"{'reference 8 spp':<22}{cmp['mae']:>8.4f}{cmp['rmse']:>8.4f}{cmp['ssim']:>8.4f}{cmp['flicker']:>9.4f}")
print()
print(f"report  {os.path.join(out, 'report.json')}")
print(f"picture {os.path.join(out, 'side_by_side.png')}  (left 8 spp, right reference)")
PY
