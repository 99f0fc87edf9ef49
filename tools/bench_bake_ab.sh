#!/bin/bash
# A plain bake (no --timings: what a production bake pays) by two cubeao binaries, alternating, so that
# the load of a shared machine falls on both alike: ms per probe, per estimator and round.
# Usage: tools/bench_bake_ab.sh BEFORE_BINARY AFTER_BINARY [SCENE (builtin:cloister)] [RES (256)] [PROBES (4)] [ROUNDS (2)]
set -euo pipefail
before=${1:?before binary}; after=${2:?after binary}
scene=${3:-builtin:cloister}; res=${4:-256}; probes=${5:-4}; rounds=${6:-2}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
"$after" place "$scene" --method path --budget "$probes" --out "$out/probes.json" >/dev/null
echo "| round | estimator | before ms/probe | after ms/probe |"
echo "|---|---|---|---|"
for round in $(seq "$rounds"); do
  for est in hsplit gtao traced; do
    row="| $round | $est"
    for bin in "$before" "$after"; do
      rm -rf "$out/cache.cubeao"*
      ms=$("$bin" bake "$scene" --probes "$out/probes.json" --out "$out/cache.cubeao" --res "$res" --estimator "$est" \
             --json 2>/dev/null | tail -1 | python3 -c 'import json, sys; print(round(json.load(sys.stdin)["ms_per_probe"]))')
      row="$row | $ms"
    done
    echo "$row |"
  done
done
