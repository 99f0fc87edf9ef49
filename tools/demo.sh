#!/bin/bash
# README command 1: the main job end to end on a built-in scene (default builtin:cloister).
# Installs what is missing, builds, and runs what exists of the pipeline today:
#   info → place probes along the camera path → bake them into probe caches (traced and
#   horizon-split, on the GPU path: llvmpipe here) with the Embree twin checking every texel, and
#   check every checksum of each cache (info --verify) → reference AO of the camera path
#   (Embree, the ground truth) → a fast low-sample reference → compare the two → report.
# `render` (projecting the probes into the camera) joins this same command when it lands.
# Environment: CUBEAO_DEMO_SCENE (default builtin:cloister), CUBEAO_DEMO_OUT (default out/demo),
# CUBEAO_DEMO_SPP (reference rays per pixel, default 128), CUBEAO_DEMO_RES (probe face size, 128).
set -euo pipefail
cd "$(dirname "$0")/.."
scene=${CUBEAO_DEMO_SCENE:-builtin:cloister}
out=${CUBEAO_DEMO_OUT:-out/demo}
spp=${CUBEAO_DEMO_SPP:-128}
res=${CUBEAO_DEMO_RES:-128}

bash tools/install-deps.sh
bash tools/build.sh --target cubeao
bin=build/cubeao

rm -rf "$out"
mkdir -p "$out"
echo "== scene"
"$bin" info "$scene" --json | tee "$out/info.log" | tail -1 >"$out/info.json"
sed '$d' "$out/info.log"
echo "== place: 4 probes along the camera path"
"$bin" place "$scene" --budget 4 --out "$out/probes.json"
device=gpu
for est in traced hsplit; do
  echo "== bake ($est, ${res}² per face, $device) into a probe cache, checked against the Embree twin at every texel"
  cache="$out/bake-$est.cubeao"
  bake=("$bin" bake "$scene" --probes "$out/probes.json" --out "$cache" --dump "$out/bake-$est-dump"
        --res "$res" --estimator "$est" --verify --json)
  if ! "${bake[@]}" --device "$device" >"$out/bake-$est.log"; then
    [ "$device" = gpu ] || exit 1
    echo "   (no usable OpenGL 4.5 context: baking on the CPU path instead)"
    device=cpu
    "${bake[@]}" --device "$device" >"$out/bake-$est.log"
  fi
  sed '$d' "$out/bake-$est.log"
  tail -1 "$out/bake-$est.log" >"$out/bake-$est.json"
  "$bin" info "$cache" --verify --json >"$out/bake-$est-info.log"
  sed -n '/verify/p' "$out/bake-$est-info.log"
  tail -1 "$out/bake-$est-info.log" >"$out/bake-$est-info.json"
done
oiiotool "$out/bake-traced-dump/probe_0001_cross.png" "$out/bake-hsplit-dump/probe_0001_cross.png" \
    --mosaic:pad=6 1x2 -o "$out/probe_cross.png"
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
bakes = {est: load(f"bake-{est}.json") for est in ("traced", "hsplit")}
caches = {est: load(f"bake-{est}-info.json") for est in ("traced", "hsplit")}
report = {"scene": info, "bake": bakes, "cache": caches, "reference": ref, "reference_8spp": fast, "compare_8spp_vs_reference": cmp,
          "images": {"side_by_side": os.path.join(out, "side_by_side.png"),
                     "probe_cross": os.path.join(out, "probe_cross.png"),
                     "reference": ref["out"], "reference_8spp": fast["out"]}}
json.dump(report, open(os.path.join(out, "report.json"), "w"), indent=1)
print()
print(f"scene      {info['scene']}: {info['triangles']} triangles, AO radius {ref['radius']:.3f}")
print(f"reference  {len(ref['frames'])} frames {ref['width']}x{ref['height']}, {ref['spp']} spp, "
      f"{ref['rays_per_s']/1e6:.1f} Mrays/s, noise (mean std. error) {ref['noise']:.4f}")
print()
where = bakes['traced'].get('renderer', 'CPU path, Embree')
print(f"{'bake':<10}{'probes':>7}{'ms/probe':>10}{'verify_mae':>12}{'AO PSNR':>9}{'B/texel':>9}   ({where}; verify_mae: against the Embree twin, same rays;")
print(f"{'':<57}AO PSNR: BC5 in the cache against the uncompressed AO)")
for est, b in bakes.items():
    print(f"{est:<10}{b['probes']:>7}{b['ms_per_probe']:>10.0f}{b['verify_mae']:>12.4f}{b['ao_psnr']:>9.1f}{caches[est]['bytes_per_texel']:>9.3f}")
print()
print(f"{'method':<22}{'MAE':>8}{'RMSE':>8}{'SSIM':>8}{'flicker':>9}   (against the {ref['spp']}-spp reference)")
print(f"{'reference 8 spp':<22}{cmp['mae']:>8.4f}{cmp['rmse']:>8.4f}{cmp['ssim']:>8.4f}{cmp['flicker']:>9.4f}")
print()
print(f"report  {os.path.join(out, 'report.json')}")
print(f"picture {os.path.join(out, 'side_by_side.png')}  (left 8 spp, right reference)")
print(f"probe   {os.path.join(out, 'probe_cross.png')}  (probe 1 unfolded: traced above, horizon-split below)")
PY
