#!/usr/bin/env bash
# Calibrates placement's error model (placement/include/cubeao/placement/error_model.h, issue 31)
# against measured walks: probe sets of several sizes and kinds baked traced at several face sizes,
# rendered along a shared walk and compared with an Embree reference; beside each measured MAE, the
# parts of its prediction (`info SCENE --probes P --camera WALK --res N --json`: served, texel and
# unserved weight), so that floor, slope and fallback are a least-squares fit (linear in them).
#
#   bash tools/calibrate_error.sh [sibenik|fzk-haus ...]
#
# Writes out/calibrate/SCENE/table.tsv (one row per probe set and face size) and prints the fit over
# every scene given (tools/fit_error_model.py). Env: FRAMES (0:120), W H (320 180), SPP (512),
# RESOLUTIONS ("128 512"), COUNTS ("6 12 24"), BIN (build/cubeao).
set -euo pipefail
cd "$(dirname "$0")/.."
shared=${CUBEAO_SHARED_DIR:-../shared}
bin=${BIN:-build/cubeao}
frames=${FRAMES:-0:120} W=${W:-320} H=${H:-180} spp=${SPP:-512}
resolutions=${RESOLUTIONS:-128 512} counts=${COUNTS:-6 12 24}
scenes=("$@")
[ ${#scenes[@]} -gt 0 ] || scenes=(sibenik fzk-haus)

tables=()
for which in "${scenes[@]}"; do
    case $which in
        sibenik) scene=$shared/scenes/sibenik/sibenik.obj; walk=$shared/scenes/sibenik/walk.json ;;
        fzk-haus) scene=/usr/share/assimp/models/IFC/AC14-FZK-Haus.ifc; walk=$shared/scenes/fzk-haus/walk.json ;;
        *) echo "calibrate_error.sh: unknown scene $which (sibenik, fzk-haus)" >&2; exit 2 ;;
    esac
    out=out/calibrate/$which
    mkdir -p "$out"
    [ -f "$out/ref/done" ] || {
        "$bin" reference "$scene" --camera "$walk" --frames "$frames" --width "$W" --height "$H" --spp "$spp" \
            --out "$out/ref" --json > "$out/ref.json" && touch "$out/ref/done"; }
    # Probe sets: the walk's eyes evenly spread (path) and the default placement at the same counts.
    sets=()
    for n in $counts; do
        # Kept once made: a cache baked from a set must keep meeting that set (a refit re-runs only `info`).
        [ -f "$out/path-$n.json" ] ||
            "$bin" place "$scene" --method path --camera "$walk" --budget "$n" --out "$out/path-$n.json" > /dev/null
        [ -f "$out/voting-$n.json" ] ||
            "$bin" place "$scene" --camera "$walk" --budget "$n" --out "$out/voting-$n.json" > /dev/null
        sets+=("path-$n" "voting-$n")
    done
    table=$out/table.tsv
    printf 'scene\tset\tres\tprobes\tmae\tpredicted\tserved\tocc\ttexel\ttexel_near\tunserved\tunserved_occ\tcapped\n' > "$table"
    for s in "${sets[@]}"; do
        for res in $resolutions; do
            cache=$out/$s-$res.cubeao
            [ -f "$cache" ] || "$bin" bake "$scene" --probes "$out/$s.json" --res "$res" --estimator traced \
                --device cpu --out "$cache" > /dev/null
            # The measured MAE is kept beside the cache: a refit with new prediction terms re-runs only `info`.
            if [ ! -f "$out/$s-$res.mae" ]; then
                "$bin" render "$scene" --cache "$cache" --camera "$walk" --frames "$frames" --width "$W" \
                    --height "$H" --out "$out/$s-$res" > /dev/null
                "$bin" compare "$out/$s-$res" "$out/ref" --json | tail -1 | python3 -c \
                    'import json,sys; print(json.load(sys.stdin)["mae"])' > "$out/$s-$res.mae"
            fi
            mae=$(cat "$out/$s-$res.mae")
            "$bin" info "$scene" --probes "$out/$s.json" --camera "$walk" --res "$res" --json | tail -1 |
                python3 -c 'import json,sys
c = json.load(sys.stdin)["probe_check"]; t = c["error_terms"]
print("\t".join(map(str, [sys.argv[1], sys.argv[2], sys.argv[3], c["probes"], sys.argv[4], c["predicted_mae"],
                           t["served_weight"], t["occluded_term"], t["texel_term"], t["texel_near_term"], t["unserved_weight"],
                           t["unserved_occluded"], t["capped_weight"]])))' \
                "$which" "$s" "$res" "$mae" >> "$table"
            tail -1 "$table"
        done
    done
    # The screen-space fallback's error on this walk (what an unserved sample shows): GTAO's MAE.
    if [ ! -f "$out/gtao.mae" ]; then
        "$bin" render "$scene" --method gtao --camera "$walk" --frames "$frames" --width "$W" --height "$H" \
            --out "$out/gtao" > /dev/null
        "$bin" compare "$out/gtao" "$out/ref" --json | tail -1 | python3 -c \
            'import json,sys; print(json.load(sys.stdin)["mae"])' > "$out/gtao.mae"
    fi
    tables+=("$table")
done
# screen = GTAO's MAE over the walks' mean occlusion (every row of a table has the same total occlusion).
screen=$(python3 - "${tables[@]}" <<'PY'
import csv, os, sys
gtao = occ = 0.0
for t in sys.argv[1:]:
    r = next(csv.DictReader(open(t), delimiter="\t"))
    gtao += float(open(os.path.join(os.path.dirname(t), "gtao.mae")).read())
    occ += float(r["occ"]) + float(r["unserved_occ"])
print(gtao / occ)
PY
)
python3 tools/fit_error_model.py --screen "$screen" "${tables[@]}"
