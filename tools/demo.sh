#!/bin/bash
# README command 1: the main job end to end on a built-in scene (default builtin:cloister).
# Installs what is missing, builds, then:
#   info → place probes (normal voting over what the camera path sees) → bake them into probe caches
#   (traced, and horizon-split for comparison; GPU path, llvmpipe here) with the Embree twin checking
#   every texel, and every checksum of each cache checked (info --verify) → render the camera path from the probes
#   and with the screen-space baselines (gtao, hbao, alchemy) → reference AO of the same path (Embree,
#   the ground truth) → compare each against it → a table, report.json and pictures.
# Environment: CUBEAO_DEMO_SCENE (default builtin:cloister), CUBEAO_DEMO_CAMERA (camera path JSON;
# default: a built-in scene's own), CUBEAO_DEMO_SIZE (image WxH; default: the camera file's),
# CUBEAO_DEMO_OUT (default out/demo), CUBEAO_DEMO_SPP (reference rays per pixel, default 256),
# CUBEAO_DEMO_RES (probe face size, 128), CUBEAO_DEMO_PROBES (most probes, 12), CUBEAO_DEMO_PLACE
# (placement method: voting, coverage, grid or path; default voting), CUBEAO_DEMO_BAKE_SPP
# (rays per traced texel, 64), CUBEAO_DEMO_DEVICE (bake on gpu, falling back to cpu; or cpu;
# CUBEAO_DEMO_DEVICE_TRACED / _HSPLIT choose per estimator), CUBEAO_DEMO_VERIFY (1: check every
# texel against Embree; 0: skip),
# CUBEAO_DEMO_REFERENCE (an existing reference directory of the same walk to reuse instead of tracing
# one), CUBEAO_BIN (a built cubeao to use; skips install and build).
# The shared walks: tools/walks.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
scene=${CUBEAO_DEMO_SCENE:-builtin:cloister}
out=${CUBEAO_DEMO_OUT:-out/demo}
spp=${CUBEAO_DEMO_SPP:-256}
res=${CUBEAO_DEMO_RES:-128}
nprobes=${CUBEAO_DEMO_PROBES:-12}
place=${CUBEAO_DEMO_PLACE:-voting}
bake_spp=${CUBEAO_DEMO_BAKE_SPP:-64}
device=${CUBEAO_DEMO_DEVICE:-gpu}
verify=${CUBEAO_DEMO_VERIFY:-1}
reference=${CUBEAO_DEMO_REFERENCE:-}
walk=()  # camera and image size, passed to place, render and reference alike
[ -z "${CUBEAO_DEMO_CAMERA:-}" ] || walk+=(--camera "$CUBEAO_DEMO_CAMERA")
if [ -n "${CUBEAO_DEMO_SIZE:-}" ]; then walk+=(--width "${CUBEAO_DEMO_SIZE%x*}" --height "${CUBEAO_DEMO_SIZE#*x}"); fi

if [ -n "${CUBEAO_BIN:-}" ]; then
  bin=$CUBEAO_BIN
else
  bash tools/install-deps.sh
  bash tools/build.sh --target cubeao
  bin=build/cubeao
fi

rm -rf "$out"
mkdir -p "$out"
echo "== scene"
"$bin" info "$scene" --json | tee "$out/info.log" | tail -1 >"$out/info.json"
sed '$d' "$out/info.log"
echo "== place: $nprobes probes ($place; fewer only where no probe lowers the predicted error)"
# The probes cover what the walk sees: its camera file, or a built-in scene's own path.
place_camera=${CUBEAO_DEMO_CAMERA:-}
[ -z "$place_camera" ] && [[ "$scene" == builtin:* ]] && place_camera=$scene
"$bin" place "$scene" --method "$place" ${place_camera:+--camera "$place_camera"} --budget "$nprobes" \
    --res "$res" --out "$out/probes.json"
for est in traced hsplit; do
  var=CUBEAO_DEMO_DEVICE_${est^^}
  dev=${!var:-$device}
  bake=("$bin" bake "$scene" --probes "$out/probes.json" --out "$out/bake-$est.cubeao" --dump "$out/bake-$est-dump"
        --res "$res" --estimator "$est" --spp "$bake_spp" --json)
  if [ "$verify" = 1 ]; then
    echo "== bake ($est, ${res}² per face, $dev) into a probe cache, checked against the Embree twin at every texel"
    bake+=(--verify)
  else
    echo "== bake ($est, ${res}² per face, $dev) into a probe cache"
  fi
  cache="$out/bake-$est.cubeao"
  if ! "${bake[@]}" --device "$dev" >"$out/bake-$est.log"; then
    [ "$dev" = gpu ] || exit 1
    echo "   (no usable OpenGL 4.5 context: baking on the CPU path instead)"
    device=cpu
    rm -f "$cache"
    "${bake[@]}" --device cpu >"$out/bake-$est.log"
  fi
  sed '$d' "$out/bake-$est.log"
  tail -1 "$out/bake-$est.log" >"$out/bake-$est.json"
  "$bin" info "$cache" --verify --json >"$out/bake-$est-info.log"
  sed '$d' "$out/bake-$est-info.log" | sed -n '/verif/p'
  tail -1 "$out/bake-$est-info.log" >"$out/bake-$est-info.json"
done
oiiotool "$out/bake-traced-dump/probe_0001_cross.png" "$out/bake-hsplit-dump/probe_0001_cross.png" \
    --mosaic:pad=6 1x2 -o "$out/probe_cross.png"

methods=(probes probes-hsplit gtao hbao alchemy)
for m in "${methods[@]}"; do
  echo "== render: $m"
  case $m in
    probes) args=(--method probes --cache "$out/bake-traced.cubeao") ;;
    probes-hsplit) args=(--method probes --cache "$out/bake-hsplit.cubeao") ;;
    *) args=(--method "$m") ;;
  esac
  "$bin" render "$scene" "${walk[@]}" "${args[@]}" --out "$out/render-$m" --json | tail -1 >"$out/render-$m.json"
done
if [ -n "$reference" ]; then
  echo "== reference: reusing $reference"
  ln -sfn "$(realpath "$reference")" "$out/reference"
  cp "$reference/reference.json" "$out/reference.json"
else
  echo "== reference: $spp rays per pixel"
  "$bin" reference "$scene" "${walk[@]}" --spp "$spp" --out "$out/reference" --json | tail -1 >"$out/reference.json"
fi
for m in "${methods[@]}"; do
  "$bin" compare "$out/render-$m" "$out/reference" --json | tail -1 >"$out/compare-$m.json"
done

# A picture: first, middle and last frame; reference | probes | gtao.
frames=($(ls "$out/reference" | grep -E '^ao_[0-9]+\.png$' | sort))
pick=("${frames[0]}" "${frames[$(( ${#frames[@]} / 2 ))]}" "${frames[-1]}")
args=()
for f in "${pick[@]}"; do args+=("$out/reference/$f" "$out/render-probes/$f" "$out/render-gtao/$f"); done
oiiotool "${args[@]}" --mosaic:pad=6 "3x${#pick[@]}" -o "$out/side_by_side.png"

python3 - "$out" "${methods[@]}" <<'PY'
import json, sys, os
out, methods = sys.argv[1], sys.argv[2:]
load = lambda n: json.load(open(os.path.join(out, n)))
info, ref = load("info.json"), load("reference.json")
bakes = {est: load(f"bake-{est}.json") for est in ("traced", "hsplit")}
caches = {est: load(f"bake-{est}-info.json") for est in ("traced", "hsplit")}
renders = {m: load(f"render-{m}.json") for m in methods}
compares = {m: load(f"compare-{m}.json") for m in methods}
report = {"scene": info, "bake": bakes, "cache": caches, "render": renders, "compare": compares, "reference": ref,
          "images": {"side_by_side": os.path.join(out, "side_by_side.png"),
                     "probe_cross": os.path.join(out, "probe_cross.png"), "reference": ref["out"]}}
json.dump(report, open(os.path.join(out, "report.json"), "w"), indent=1)
print()
print(f"scene      {info['scene']}: {info['triangles']} triangles, AO radius {ref['radius']:.3f}")
print(f"reference  {len(ref['frames'])} frames {ref['width']}x{ref['height']}, {ref['spp']} spp, "
      f"noise (std. error) {ref['noise']:.4f}: part of every MAE below")
print()
print(f"{'bake':<10}{'probes':>7}{'ms/probe':>10}{'verify_mae':>12}{'AO PSNR':>9}{'B/texel':>9}   device")
for est, b in bakes.items():
    where = f"GPU path ({b['renderer']})" if 'renderer' in b else "CPU path (Embree)"
    print(f"{est:<10}{b['probes']:>7}{b['ms_per_probe']:>10.0f}{b.get('verify_mae', float('nan')):>12.4f}{b['ao_psnr']:>9.1f}"
          f"{caches[est]['bytes_per_texel']:>9.3f}   {where}")
print()
print(f"{'method':<15}{'MAE':>8}{'SSIM':>8}{'flicker':>9}{'AO ms':>8}{'uncovered':>11}   (against the reference)")
for m in methods:
    c, r = compares[m], renders[m]
    unc = f"{100 * r['uncovered_fraction']:.1f} %" if 'uncovered_fraction' in r else "-"
    print(f"{m:<15}{c['mae']:>8.4f}{c['ssim']:>8.4f}{c['flicker']:>9.4f}{r['timings_ms']['ao']:>8.1f}{unc:>11}")
print()
print(f"report  {os.path.join(out, 'report.json')}")
print(f"picture {os.path.join(out, 'side_by_side.png')}  (rows: first, middle, last frame; reference | probes | gtao)")
print(f"probe   {os.path.join(out, 'probe_cross.png')}  (probe 1 unfolded: traced above, horizon-split below)")
PY
"$bin" report "$out" --out "$out/report.html" >/dev/null
echo "page    $out/report.html  (one self-contained HTML page: table, frames, error maps, charts, probes from above)"
