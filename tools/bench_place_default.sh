#!/usr/bin/env bash
# Issue 31's figures for the default placement on the shared walks: `place` as a user runs it (with the
# walk, and without it for a building nobody has walked yet), and on each model with every face reversed
# and with a random half reversed, each baked traced at 512² (64 rays, CPU), rendered along the whole
# walk and compared with the reference tools/calibrate_error.sh traced (run that first: its reference
# and its path sets are reused here). A reversed model is compared with the original's reference: the
# geometry, and so the true AO, is the same.
#
#   bash tools/bench_place_default.sh [sibenik|fzk-haus ...]
#
# Prints one row per run: probes, predicted MAE, measured MAE, flicker, and the MAE against the path set
# of one probe per 10 frames. Env: BIN (build/cubeao), FRAMES/W/H as calibrate_error.sh; DEFAULT=, LIVE=,
# NO_WALK= and REVERSED= (empty) skip the default run, live placement's (and voting at its count), the
# runs without the walk (the longest) and the reversed models.
set -euo pipefail
cd "$(dirname "$0")/.."
shared=${CUBEAO_SHARED_DIR:-../shared}
bin=${BIN:-build/cubeao}
frames=${FRAMES:-0:120} W=${W:-320} H=${H:-180}
scenes=("$@")
[ ${#scenes[@]} -gt 0 ] || scenes=(sibenik fzk-haus)

# reversed SRC DST all|half: the OBJ with each face's corners reversed (all, or a fixed random half) and
# its normals dropped, as a CAD export that winds faces the other way gives it.
reversed() {
    python3 - "$1" "$2" "$3" <<'PY'
import random, sys
src, dst, mode = sys.argv[1:]
rng = random.Random(31)
with open(src) as f, open(dst, "w") as out:
    for line in f:
        if line.startswith("vn "):
            continue
        if line.startswith("f "):
            corners = [c.split("/")[0] for c in line.split()[1:]]
            if mode == "all" or rng.random() < 0.5:
                corners.reverse()
            line = "f " + " ".join(corners) + "\n"
        out.write(line)
PY
}

# run NAME SCENE OUT PLACE_ARGS...: place, bake, render, compare; one row.
run() {
    local name=$1 scene=$2 out=$3
    shift 3
    "$bin" place "$scene" --out "$out/$name.json" --json "$@" | tail -1 > "$out/$name.place.json"
    rm -rf "$out/$name.cubeao" "$out/$name.cubeao".part-*  # bake resumes a cache: not one of another probe set
    "$bin" bake "$scene" --probes "$out/$name.json" --res 512 --estimator traced --device cpu \
        --out "$out/$name.cubeao" --json | tail -1 > "$out/$name.bake.json"
    "$bin" render "$scene" --cache "$out/$name.cubeao" --camera "$walk" --frames "$frames" --width "$W" \
        --height "$H" --out "$out/$name" > /dev/null
    "$bin" compare "$out/$name" "$ref" --json | tail -1 > "$out/$name.compare.json"
    python3 - "$name" "$out" "$pathMae" <<'PY'
import json, os, sys
name, out, path = sys.argv[1], sys.argv[2], float(sys.argv[3])
place = json.load(open(f"{out}/{name}.place.json"))
cmp = json.load(open(f"{out}/{name}.compare.json"))
size = os.path.getsize(f"{out}/{name}.cubeao")
print(f"{name:16} probes {place['probes']:3}  predicted {place['predicted_mae']:.4f}  measured {cmp['mae']:.4f}"
      f"  flicker {cmp['flicker']:.4f}  x path {cmp['mae'] / path:.3f}  cache {size / 2**20:.1f} MiB"
      f"  stop {place.get('stop')}")
PY
}

for which in "${scenes[@]}"; do
    case $which in
        sibenik) scene=$shared/scenes/sibenik/sibenik.obj; walk=$shared/scenes/sibenik/walk.json ;;
        fzk-haus) scene=/usr/share/assimp/models/IFC/AC14-FZK-Haus.ifc; walk=$shared/scenes/fzk-haus/walk.json ;;
        *) echo "bench_place_default.sh: unknown scene $which (sibenik, fzk-haus)" >&2; exit 2 ;;
    esac
    cal=out/calibrate/$which ref=out/calibrate/$which/ref
    [ -f "$ref/done" ] || { echo "bench_place_default.sh: run tools/calibrate_error.sh $which first" >&2; exit 1; }
    out=out/place-default/$which
    mkdir -p "$out"
    pathMae=$(python3 - "$cal/table.tsv" <<'PY'
import csv, sys
rows = [r for r in csv.DictReader(open(sys.argv[1]), delimiter="\t") if r["set"] == "path-12" and r["res"] == "512"]
print(rows[0]["mae"])
PY
)
    echo "== $which: path set of 12 (one probe per 10 frames) at 512²: MAE $pathMae"
    if [ -n "${DEFAULT-1}" ]; then run default "$scene" "$out" --camera "$walk"; fi
    if [ -n "${LIVE-1}" ]; then
        # Live placement's objective along the walk (`place --method live`, the viewer's loop run offline),
        # and voting at the count it ended with.
        run live "$scene" "$out" --camera "$walk" --method live
        n=$(python3 -c "import json, sys; print(json.load(open(sys.argv[1]))['probes'])" "$out/live.place.json")
        run "voting-$n" "$scene" "$out" --camera "$walk" --budget "$n"
    fi
    if [ -n "${REVERSED-1}" ]; then
        # A model that is not an OBJ (FZK-Haus is IFC): its triangles as cubeao loads them, then reversed.
        src=$scene
        if [ "${scene##*.}" != obj ]; then
            "$bin" info "$scene" --write-obj "$out/$which.obj" > /dev/null
            src=$out/$which.obj
        fi
        for mode in all half; do
            reversed "$src" "$out/$which-$mode.obj" "$mode"
            run "reversed-$mode" "$out/$which-$mode.obj" "$out" --camera "$walk"
        done
    fi
    if [ -n "${NO_WALK-1}" ]; then run no-walk "$scene" "$out"; fi
done
