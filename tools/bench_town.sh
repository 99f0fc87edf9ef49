#!/bin/bash
# Issue 16's large-scene figures: every stage of the pipeline on builtin:town at each size, with wall
# time and peak resident memory (`/usr/bin/time`, and the stage's own `peak_rss_mb`), written to
# out/bench-town/report.md and report.json.
#   import  `info builtin:town:S`                         (build the town, repair, hash)
#   place   `place builtin:town:S --method voting`        (the normal-voting voxel grid, greedy cover)
#   bake    the first CUBEAO_TOWN_BAKE probes of that set, traced, GPU path (llvmpipe here) and CPU path
#   render  `bench render --synthetic` along the town's walk: 20 probes against CUBEAO_TOWN_PROBES
#           probes at 256² under a 512 MB GPU budget (synthetic payloads: the timing does not depend on
#           the AO values; baking thousands of probes at 256² on llvmpipe would take a day)
# Usage: bash tools/bench_town.sh [SIZE...]   (default: 2m 10m)
# Environment: CUBEAO_BIN (default build/cubeao), CUBEAO_TOWN_BAKE (4), CUBEAO_TOWN_RES (bake face size,
# 128), CUBEAO_TOWN_SPP (rays per traced texel, 32), CUBEAO_TOWN_PROBES (2000), CUBEAO_TOWN_STAGES
# ("import place bake render"), CUBEAO_TOWN_RADIUS (AO radius, 2 m: the default 2 % of a town's diagonal
# is a street wide).
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${CUBEAO_BIN:-build/cubeao}
[ -x "$bin" ] || { bash tools/install-deps.sh; bash tools/build.sh --target cubeao; }
sizes=("$@")
[ ${#sizes[@]} -gt 0 ] || sizes=(2m 10m)
nbake=${CUBEAO_TOWN_BAKE:-4}
res=${CUBEAO_TOWN_RES:-128}
spp=${CUBEAO_TOWN_SPP:-32}
nprobes=${CUBEAO_TOWN_PROBES:-2000}
stages=${CUBEAO_TOWN_STAGES:-import place bake render}
radius=${CUBEAO_TOWN_RADIUS:-2}
out=out/bench-town
mkdir -p "$out"
export CUBEAO_PROGRESS=lines

# Runs a stage: its JSON (last stdout line) with "wall_s" and "max_rss_mb" from /usr/bin/time added.
stage() {
  local name=$1
  shift
  local log="$out/$name.log"
  echo "bench-town: $name: $*" >&2
  if ! /usr/bin/time -f "%e %M" -o "$out/$name.time" "$@" >"$log" 2>"$log.err"; then
    echo "bench-town: $name failed; see $log.err" >&2
    tail -5 "$log.err" >&2
    echo "{\"stage\": \"$name\", \"failed\": true}"
    return 0
  fi
  python3 - "$name" "$log" "$out/$name.time" <<'EOF'
import json, sys
name, log, timing = sys.argv[1:]
last = [l for l in open(log) if l.strip()][-1]
j = json.loads(last)
wall, kib = open(timing).read().split()[-2:]
j.update({"stage": name, "wall_s": float(wall), "max_rss_mb": int(kib) / 1024})
print(json.dumps(j))
EOF
}

results="$out/results.jsonl"
: >"$results"
for size in "${sizes[@]}"; do
  scene="builtin:town:$size"
  for s in $stages; do
    case $s in
      import) stage "import-$size" "$bin" info "$scene" --json >>"$results" ;;
      place)
        stage "place-$size" "$bin" place "$scene" --method voting --radius "$radius" --out "$out/probes-$size.json" \
          --json >>"$results" ;;
      bake)
        python3 - "$out/probes-$size.json" "$out/bake-probes-$size.json" "$nbake" <<'EOF'
import json, sys
src, dst, n = sys.argv[1], sys.argv[2], int(sys.argv[3])
p = json.load(open(src))
json.dump({"version": 1, "probes": p["probes"][:n]}, open(dst, "w"))
EOF
        for dev in gpu cpu; do
          stage "bake-$dev-$size" "$bin" bake "$scene" --probes "$out/bake-probes-$size.json" \
            --out "$out/bake-$dev-$size.cubeao" --res "$res" --spp "$spp" --radius "$radius" --device "$dev" \
            --json >>"$results"
          rm -f "$out/bake-$dev-$size.cubeao"
        done ;;
      render)
        stage "render-$size" "$bin" bench render --scene "$scene" --synthetic --probes "20,$nprobes" --res 256 \
          --gpu-budget-mb 512 --width 640 --height 360 --frames 5 --rounds 3 --methods probes,gtao \
          --keep-caches "$out/caches" --json >>"$results" ;;
      *) echo "bench-town: unknown stage $s" >&2; exit 2 ;;
    esac
  done
done

python3 - "$results" "$out" <<'EOF'
import json, sys
rows = [json.loads(l) for l in open(sys.argv[1]) if l.strip()]
json.dump(rows, open(sys.argv[2] + "/report.json", "w"), indent=1)
lines = ["| stage | wall s | peak RSS MB | figures |", "|---|---:|---:|---|"]
for r in rows:
    if r.get("failed"):
        lines.append(f"| {r['stage']} | failed | | |")
        continue
    st = r["stage"]
    if st.startswith("import"):
        fig = f"{r['triangles']:,} triangles, {r['vertices']:,} vertices"
    elif st.startswith("place"):
        fig = f"{r['probes']} probes, coverage {r.get('coverage', 0):.3f}"
    elif st.startswith("bake"):
        fig = f"{r['probes']} probes, {r['ms_per_probe']:.0f} ms/probe"
    else:  # the sweep: frame (G-buffer + AO + blur) per probe count, against the fewest probes
        fig = "; ".join(f"{w['probes']} probes: {w['timings_ms']['gpu_total']:.0f} ms/frame "
                        f"(x{w['frame_ratio']:.2f}), {w['residency']['resident']} resident of "
                        f"{w['residency']['slots']} slots, {w['gpu_bytes'] / 2**20:.0f} MiB, "
                        f"screen space {100 * w['screen_space_fraction']:.1f} %" for w in r["sweep"])
    lines.append(f"| {st} | {r['wall_s']:.1f} | {r['max_rss_mb']:.0f} | {fig} |")
open(sys.argv[2] + "/report.md", "w").write("\n".join(lines) + "\n")
print("\n".join(lines))
EOF
