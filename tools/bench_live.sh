#!/bin/bash
# Issue 14's live-placement figures (docs/BENCHMARKS.md "Walkthrough viewer and live placement"), on a
# shared walk under Xvfb, written to out/bench-live/NAME/report.json:
#  1. live: cubeao-view walks the path from an empty cache with live placement (fast hsplit bakes in
#     time slices), settles the bake queue, re-bakes every probe with traced while idle, saves;
#     coverage of the walk, probes placed, frame ms of the walk's frames;
#  2. without: the same walk in the viewer with the saved cache and no live placement: the ratio of
#     the walk's frame times (wall clock) is the cost of placing and baking while walking;
#  3. quality: `render` + `compare` of the walk with the live probes (after the re-bake) and with
#     `place --method voting` at the same probe count, baked traced at the same resolution.
# Usage: bash tools/bench_live.sh [sibenik|fzk-haus]
# Environment: CUBEAO_BIN, CUBEAO_VIEW_BIN (build/cubeao, build/cubeao-view), CUBEAO_LIVE_SIZE (160x90),
# CUBEAO_LIVE_RES (128), CUBEAO_LIVE_BAKE_MS (8), CUBEAO_LIVE_TARGET (0.95), CUBEAO_LIVE_SPP (reference
# rays, 256), CUBEAO_LIVE_TAG (suffix of the output directory). The reference is reused from out/place-walks/NAME/reference (tools/bench_place.sh) when
# its size matches, else traced here.
set -euo pipefail
cd "$(dirname "$0")/.."
source tools/walk_scenes.sh
name=${1:-sibenik}
bin=${CUBEAO_BIN:-build/cubeao}
view=${CUBEAO_VIEW_BIN:-build/cubeao-view}
size=${CUBEAO_LIVE_SIZE:-160x90}
res=${CUBEAO_LIVE_RES:-128}
bake_ms=${CUBEAO_LIVE_BAKE_MS:-8}
target=${CUBEAO_LIVE_TARGET:-0.95}
spp=${CUBEAO_LIVE_SPP:-256}
w=${size%x*}
h=${size#*x}
walk_scene "$name" bench_live.sh
camera=$walk
frames=$(python3 -c "import json,sys; print(len(json.load(open(sys.argv[1]))['frames']))" "$camera")
out=out/bench-live/$name${CUBEAO_LIVE_TAG:+-$CUBEAO_LIVE_TAG}
mkdir -p "$out"
xrun=()
[ -z "${DISPLAY:-}" ] && xrun=(xvfb-run -a -s "-screen 0 1280x800x24")

ref=out/place-walks/$name/reference
if [ ! -f "$ref/ao_0000.exr" ] || ! oiiotool --info "$ref/ao_0000.exr" | grep -Eq " $w x +$h,"; then
  ref=$out/reference
  "$bin" reference "$scene" --camera "$camera" --width "$w" --height "$h" --spp "$spp" --out "$ref" --json >"$out/reference.json"
fi

echo "== 1. live placement along the walk ($frames frames at $size, probes at ${res}², ${bake_ms} ms a frame)"
cat >"$out/live.txt" <<EOF
size $w $h
play 0 $frames
settle 100000
save $out/live-fast.cubeao
rebake 1000000
save $out/live.cubeao
quit
EOF
/usr/bin/time -v -o "$out/live.time" "${xrun[@]}" "$view" "$scene" --camera "$camera" --live --live-res "$res" \
  --bake-ms "$bake_ms" --coverage-target "$target" --no-vsync --script "$out/live.txt" --stats "$out/live.json" \
  >"$out/live.log" 2>&1

echo "== 2. the same walk with the saved cache, no live placement"
printf 'size %s %s\nplay 0 %s\nquit\n' "$w" "$h" "$frames" >"$out/walk.txt"
"${xrun[@]}" "$view" "$scene" --camera "$camera" --cache "$out/live.cubeao" --no-vsync --script "$out/walk.txt" \
  --stats "$out/walk.json" >"$out/walk.log" 2>&1

echo "== 3. quality: live probes (re-baked traced) and voting at the same count"
n=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['live']['placed'])" "$out/live.json")
echo "   $n probes placed"
"$bin" render "$scene" --camera "$camera" --cache "$out/live.cubeao" --width "$w" --height "$h" --out "$out/render-live" --json >"$out/render-live.json"
"$bin" compare "$out/render-live" "$ref" --json >"$out/compare-live.json"
"$bin" place "$scene" --camera "$camera" --method voting --budget "$n" --res "$res" \
  --texels-per-radius "$(python3 -c "print(16 * $res / 512)")" --out "$out/voting.json" --json >"$out/place-voting.json"
"$bin" bake "$scene" --probes "$out/voting.json" --res "$res" --estimator traced --out "$out/voting.cubeao" --json >"$out/bake-voting.json"
"$bin" render "$scene" --camera "$camera" --cache "$out/voting.cubeao" --width "$w" --height "$h" --out "$out/render-voting" --json >"$out/render-voting.json"
"$bin" compare "$out/render-voting" "$ref" --json >"$out/compare-voting.json"

python3 - "$out" <<'EOF'
import json, sys, statistics
out = sys.argv[1]
live = json.load(open(f"{out}/live.json"))
walk = json.load(open(f"{out}/walk.json"))
def walk_ms(stats):
    # The walk's frames: those rendered while the script's `play` line (line 2) ran.
    frames = [f for f in stats["frame_log"]["frames"] if f[2] == 2]
    return statistics.median(f[0] for f in frames), statistics.mean(f[0] for f in frames), \
        statistics.mean(f[1] for f in frames), len(frames)
lm, lmean, lbake, ln = walk_ms(live)
wm, wmean, _, wn = walk_ms(walk)
last = lambda f: json.loads(open(f).read().strip().splitlines()[-1])
cl = last(f"{out}/compare-live.json")
cv = last(f"{out}/compare-voting.json")
pick = lambda c: {k: c[k] for k in ("mae", "rmse", "flicker")}
report = {
    "probes_placed": live["live"]["placed"],
    "rebaked": live["live"]["rebaked"],
    "walk_coverage_mean": live["live"].get("walk_coverage_mean"),
    "walk_coverage_min": live["live"].get("walk_coverage_min"),
    "walk_frames": ln,
    "walk_frame_ms_median_live": lm, "walk_frame_ms_median_without": wm,
    "walk_frame_ms_mean_live": lmean, "walk_frame_ms_mean_without": wmean,
    "ratio_median": lm / wm, "ratio_mean": lmean / wmean,
    "bake_ms_per_walk_frame": lbake,
    "total_frames_live": live["frames"],
    "compare_live": pick(cl), "compare_voting": pick(cv),
}
json.dump(report, open(f"{out}/report.json", "w"), indent=2)
print(json.dumps(report, indent=2))
EOF
