#!/usr/bin/env python3
"""An upper bound for placement at a given count (issue 31): greedy on the *measured* walk MAE.

Placement chooses probes by a predicted error; this script chooses them by the error it measures.
Every candidate is baked once (one single-probe cache each, `bake --shard I/N`); a probe set is a
`merge` of its members' caches, rendered along a subsampled walk and compared with an Embree
reference. Greedy: each step adds the candidate whose set renders with the least MAE; then swap
passes replace each member by the candidate that lowers the MAE most, until none does. What this
reaches at N probes is what a placement that chose from the same candidates by the measured error
would reach: if it is above a target, no objective over these candidates meets that target. Every
set measured is kept in OUT_DIR/measured.json (a table to fit an error model to).

    python3 tools/oracle_place.py SCENE WALK OUT_DIR COUNT CANDIDATES.json [SET.json ...]

CANDIDATES.json and each SET.json are probes.json files; the SETs (e.g. path's and the default
placement's) are measured on the same subsampled walk for comparison and their probes join the
candidates. Env: BIN (build/cubeao), RES (512), STRIDE (3: every 3rd frame of the walk), W H (160 90),
SPP (512), SWAPS (1: swap passes), GREEDY (1; 0: no greedy, no swaps), RANDOM_SETS (0: random sets of
COUNT measured first, RANDOM_SEED 1).
"""
import json
import os
import random
import subprocess
import sys

BIN = os.environ.get("BIN", "build/cubeao")
RES = os.environ.get("RES", "512")
STRIDE = int(os.environ.get("STRIDE", "3"))
W, H = os.environ.get("W", "160"), os.environ.get("H", "90")
SPP = os.environ.get("SPP", "512")
SWAPS = int(os.environ.get("SWAPS", "1"))
GREEDY = int(os.environ.get("GREEDY", "1"))
RANDOM_SETS = int(os.environ.get("RANDOM_SETS", "0"))
RANDOM_SEED = int(os.environ.get("RANDOM_SEED", "1"))


def run(*args):
    subprocess.run([BIN, *args], check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def positions(path):
    return [tuple(round(c, 4) for c in p["pos"]) for p in json.load(open(path))["probes"]]


def main():
    scene, walk, out, count, cand_file, *sets = sys.argv[1:]
    count = int(count)
    os.makedirs(out, exist_ok=True)
    # The walk, every STRIDE-th frame (a camera path is a list of frames).
    path = json.load(open(walk))
    path["frames"] = path["frames"][::STRIDE]
    sub = os.path.join(out, "walk.json")
    json.dump(path, open(sub, "w"))
    ref = os.path.join(out, "ref")
    if not os.path.exists(ref + ".done"):
        run("reference", scene, "--camera", sub, "--width", W, "--height", H, "--spp", SPP, "--out", ref)
        open(ref + ".done", "w").close()

    cands = []
    for f in [cand_file, *sets]:
        for p in positions(f):
            if p not in cands:
                cands.append(p)
    cand_json = os.path.join(out, "candidates.json")
    json.dump({"version": 1, "probes": [{"pos": list(p)} for p in cands]}, open(cand_json, "w"))
    n = len(cands)
    caches = [os.path.join(out, f"c{i:03d}.cubeao") for i in range(n)]
    for i, c in enumerate(caches):
        if not os.path.exists(c):
            run("bake", scene, "--probes", cand_json, "--shard", f"{i}/{n}", "--res", RES,
                "--estimator", "traced", "--device", "cpu", "--out", c)
        print(f"baked {i + 1}/{n}", file=sys.stderr, flush=True)

    memo = {}

    def mae(members):
        key = tuple(sorted(members))
        if key in memo:
            return memo[key]
        name = os.path.join(out, "set")
        run("merge", name + ".cubeao", *[caches[i] for i in key])
        run("render", scene, "--cache", name + ".cubeao", "--camera", sub, "--width", W, "--height", H,
            "--out", name)
        r = subprocess.run([BIN, "compare", name, ref, "--json"], check=True, capture_output=True, text=True)
        memo[key] = json.loads(r.stdout.strip().splitlines()[-1])["mae"]
        return memo[key]

    result = {"candidates": n, "count": count, "sets": {}}
    for f in sets:
        members = [cands.index(p) for p in positions(f)]
        result["sets"][os.path.basename(f)] = mae(members)
        print(f"{f}: {len(members)} probes, MAE {result['sets'][os.path.basename(f)]:.5f}", flush=True)

    # Random sets of COUNT (a spread of good and bad sets to fit an error model to).
    rng = random.Random(RANDOM_SEED)
    for r in range(RANDOM_SETS):
        members = rng.sample(range(n), count)
        print(f"random {r + 1}/{RANDOM_SETS}: MAE {mae(members):.5f}", flush=True)

    chosen = []
    while GREEDY and len(chosen) < count:
        best = min((i for i in range(n) if i not in chosen), key=lambda i: mae(chosen + [i]))
        chosen.append(best)
        print(f"greedy {len(chosen)}: + {cands[best]} MAE {mae(chosen):.5f}", flush=True)
    result["greedy"] = mae(chosen) if chosen else None
    for sweep in range(SWAPS if chosen else 0):
        improved = False
        for k in range(count):
            rest = chosen[:k] + chosen[k + 1:]
            best = min((i for i in range(n) if i not in rest), key=lambda i: mae(rest + [i]))
            if mae(rest + [best]) < mae(chosen):
                chosen = rest[:k] + [best] + rest[k:]
                improved = True
                print(f"swap {sweep + 1}.{k + 1}: MAE {mae(chosen):.5f}", flush=True)
        if not improved:
            break
    result["oracle"] = mae(chosen) if chosen else None
    result["oracle_probes"] = [list(cands[i]) for i in chosen]
    result["renders"] = len(memo)
    # Every set measured, for fitting an error model to (the members as candidate indices).
    json.dump({"candidates": [list(p) for p in cands],
               "sets": [{"members": list(k), "mae": v} for k, v in memo.items()]},
              open(os.path.join(out, "measured.json"), "w"))
    if chosen:
        json.dump({"version": 1, "probes": [{"pos": list(cands[i])} for i in chosen]},
                  open(os.path.join(out, "oracle.json"), "w"))
    json.dump(result, open(os.path.join(out, "result.json"), "w"), indent=1)
    print(json.dumps(result), flush=True)


if __name__ == "__main__":
    main()
