#!/bin/bash
# Issue 13's run-time figures (DESIGN.md §4 "Run time that grows"; probes streamed into a pool of atlas
# slots under a GPU budget, uncovered pixels filled by GTAO), written to out/bench-residency/report.md
# and report.json:
#  1. sweep: `bench render --synthetic` at 256² faces, caches of 20, 100, 1,000 and 10,000 probes
#     (made-up payloads: 10,000 probes are 4.4 GB, written in seconds from a few shared payloads),
#     every count's probe pass (projection + residency + GTAO fill) timed in interleaved rounds under
#     the budget; target: each count's frame within 10 % of the 20-probe cache's. The caches are kept
#     in $CUBEAO_RESIDENCY_DIR and reused by the next steps (and by the next run of this script).
#  2. render: `cubeao render --gpu-budget-mb` over the walk with each kept cache (100, 1,000, 10,000
#     probes) and the 20-probe cache without a budget: peak RSS (target: independent of the count),
#     median per-pass ms, residency stats, where the pixels' AO came from.
#  3. 1080p: `bench render --methods probes,gtao` with the 10,000-probe cache under the budget: the
#     probes' AO pass against gtao's in one run (target: <= 0.2x).
# Usage: bash tools/bench_residency.sh
# Environment: CUBEAO_BIN (default build/cubeao), CUBEAO_RESIDENCY_SCENE (builtin:cloister),
# CUBEAO_RESIDENCY_DIR (caches, out/bench-residency/caches), CUBEAO_RESIDENCY_BUDGET (MiB, 256),
# CUBEAO_RESIDENCY_RES (256), CUBEAO_RESIDENCY_COUNTS ("20 100 1000 10000"), CUBEAO_RESIDENCY_SIZE
# (sweep and render WxH, 640x360), CUBEAO_RESIDENCY_FRAMES (render frame range A:B, default all),
# CUBEAO_RESIDENCY_SWEEP_FRAMES / _ROUNDS (3 / 3), CUBEAO_RESIDENCY_PARTS ("sweep render hd"),
# CUBEAO_RESIDENCY_CLEAN=1 removes the caches at the end.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${CUBEAO_BIN:-build/cubeao}
if [ ! -x "$bin" ]; then
  bash tools/build.sh --target cubeao
fi
scene=${CUBEAO_RESIDENCY_SCENE:-builtin:cloister}
out=out/bench-residency
dir=${CUBEAO_RESIDENCY_DIR:-$out/caches}
budget=${CUBEAO_RESIDENCY_BUDGET:-256}
res=${CUBEAO_RESIDENCY_RES:-256}
counts=${CUBEAO_RESIDENCY_COUNTS:-20 100 1000 10000}
size=${CUBEAO_RESIDENCY_SIZE:-640x360}
frames=${CUBEAO_RESIDENCY_FRAMES:-}
sweep_frames=${CUBEAO_RESIDENCY_SWEEP_FRAMES:-3}
sweep_rounds=${CUBEAO_RESIDENCY_SWEEP_ROUNDS:-3}
parts=${CUBEAO_RESIDENCY_PARTS:-sweep render hd}
w=${size%x*} h=${size#*x}
mkdir -p "$out" "$dir"
smallest=$(echo $counts | tr ' ' '\n' | sort -n | head -1)
largest=$(echo $counts | tr ' ' '\n' | sort -n | tail -1)

# The caches: step 1 writes them (or reuses kept ones with the same count and parameters).
if [[ " $parts " == *" sweep "* ]]; then
  echo "== sweep: $counts synthetic probes at ${res}², budget $budget MiB, ${w}x$h"
  "$bin" bench render --scene "$scene" --synthetic --res "$res" --probes "$(echo $counts | tr ' ' ,)" \
      --gpu-budget-mb "$budget" --methods probes --keep-caches "$dir" --width "$w" --height "$h" \
      --frames "$sweep_frames" --rounds "$sweep_rounds" --json | tee "$out/sweep.log" | tail -1 >"$out/sweep.json"
fi

# render NAME CACHE BUDGET: one `render` process over the walk; its JSON to $out/render-NAME.json.
render() {
  local name=$1 cache=$2 mb=$3
  echo "== render: $name ($cache, budget $mb MiB)"
  rm -rf "$out/render-$name"
  "$bin" render "$scene" --cache "$cache" --gpu-budget-mb "$mb" --width "$w" --height "$h" \
      ${frames:+--frames "$frames"} --out "$out/render-$name" --json | tail -1 >"$out/render-$name.json"
  rm -rf "$out/render-$name"  # the images: only the figures are kept
}
if [[ " $parts " == *" render "* ]]; then
  rm -f "$out"/render-*.json
  for n in $counts; do
    [ -f "$dir/synthetic_${res}_$n.cubeao" ] || { echo "no $dir/synthetic_${res}_$n.cubeao: run the sweep part"; exit 1; }
  done
  render "$smallest-all-resident" "$dir/synthetic_${res}_$smallest.cubeao" 0
  for n in $counts; do
    [ "$n" = "$smallest" ] || render "$n-budget-$budget" "$dir/synthetic_${res}_$n.cubeao" "$budget"
  done
fi

if [[ " $parts " == *" hd "* ]]; then
  echo "== 1080p: probes ($smallest and $largest, budget $budget MiB) against gtao"
  "$bin" bench render --scene "$scene" --synthetic --res "$res" --probes "$smallest,$largest" --gpu-budget-mb "$budget" \
      --methods probes,gtao --keep-caches "$dir" --width 1920 --height 1080 --frames "$sweep_frames" \
      --rounds "$sweep_rounds" --json | tee "$out/hd.log" | tail -1 >"$out/hd.json"
fi

# The report: every part whose figures are in $out (this run's, or an earlier run's for parts left out).
python3 - "$out" <<'PY'
import glob, json, os, sys
out = sys.argv[1]
report, lines = {}, []
def mb(b): return b / 2**20
if os.path.exists(f"{out}/sweep.json"):
    j = report["sweep"] = json.load(open(f"{out}/sweep.json"))
    lines += [f"Sweep ({j['width']}x{j['height']}, {len(j['frames'])} frames x {j['rounds']} rounds, "
              f"budget {j['sweep_caches']['gpu_budget_mb']} MiB, {j['renderer']}):", "",
              "| probes | cache GB | slots | resident | loads | evictions | max upload MiB | GPU MiB | frame ms | x smallest | AO ms | x smallest | GTAO-filled px |",
              "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in j["sweep"]:
        s, t = r["residency"], r["timings_ms"]
        lines.append(f"| {r['probes']} | {r['cache_bytes'] / 1e9:.2f} | {s['slots']} | {s['resident']} | {s['loads']} | "
                     f"{s['evictions']} | {mb(s['max_frame_upload_bytes']):.2f} | {mb(r['gpu_bytes']):.1f} | "
                     f"{t['gpu_total']:.1f} | {r['frame_ratio']:.3f} | {t['ao']:.1f} | {r['ao_ratio']:.3f} | "
                     f"{100 * r['screen_space_fraction']:.1f} % |")
    lines += ["", f"Largest frame / smallest: {j['targets']['sweep_max_frame_ratio']:.3f} (target <= 1.10: "
              f"{'met' if j['targets']['sweep_within_10pct'] else 'missed'})", ""]
renders = sorted(glob.glob(f"{out}/render-*.json"), key=lambda p: int(os.path.basename(p).split("-")[1]))
if renders:
    report["render"] = {}
    lines += ["Render over the walk (one process per cache):", "",
              "| cache | budget MiB | frames | peak RSS MB | G-buffer | AO | blur | frame ms | slots | resident | loads | evictions | max upload MiB | bound MiB | GPU MiB | probes px | GTAO px |",
              "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for p in renders:
        j = json.load(open(p))
        name = os.path.basename(p)[len("render-"):-len(".json")]
        report["render"][name] = j
        s, t, px = j["residency"], j["timings_ms"], j["pixels"]
        lines.append(f"| {j['probes']} | {s['gpu_budget_mb']:g} | {len(j['frames'])} | {j['peak_rss_mb']:.0f} | "
                     f"{t['gbuffer']:.1f} | {t['ao']:.1f} | {t['blur']:.1f} | {t['gpu_total']:.1f} | {s['slots']} | "
                     f"{s['resident']} | {s['loads']} | {s['evictions']} | {mb(s['max_frame_upload_bytes']):.2f} | "
                     f"{mb(s['upload_bound_bytes']):.2f} | {mb(s['gpu_bytes']):.1f} | {100 * px['probes']:.1f} % | "
                     f"{100 * px['screen_space']:.1f} % |")
    lines.append("")
if os.path.exists(f"{out}/hd.json"):
    j = report["hd"] = json.load(open(f"{out}/hd.json"))
    g = j["methods"]["gtao"]
    lines += [f"1080p, {len(j['frames'])} frames x {j['rounds']} rounds, budget {j['sweep_caches']['gpu_budget_mb']} MiB:",
              "", "| method | probes | slots | AO ms | x gtao | AO + blur ms | frame ms | GTAO-filled px |",
              "|---|---|---|---|---|---|---|---|"]
    for p in j["sweep"]:
        lines.append(f"| probes | {p['probes']} | {p['residency']['slots']} | {p['timings_ms']['ao']:.1f} | "
                     f"{p['timings_ms']['ao'] / g['timings_ms']['ao']:.3f} | {p['timings_ms']['ao_blur']:.1f} | "
                     f"{p['timings_ms']['gpu_total']:.1f} | {100 * p['screen_space_fraction']:.1f} % |")
    lines += [f"| gtao | - | - | {g['timings_ms']['ao']:.1f} | 1 | {g['timings_ms']['ao_blur']:.1f} | "
              f"{g['timings_ms']['gpu_total']:.1f} | - |", "",
              f"probes ({j['methods']['probes']['probes']}) / gtao, AO pass: {j['targets']['probes_to_gtao_ao']:.3f} (target <= 0.2: "
              f"{'met' if j['targets']['probes_to_gtao_ao'] <= 0.2 else 'missed'})", ""]
json.dump(report, open(f"{out}/report.json", "w"), indent=1)
open(f"{out}/report.md", "w").write("\n".join(lines) + "\n")
print("\n".join(lines))
PY

if [ "${CUBEAO_RESIDENCY_CLEAN:-0}" = 1 ]; then
  rm -f "$dir"/synthetic_"${res}"_*.cubeao
fi
