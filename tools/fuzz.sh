#!/bin/bash
# The libFuzzer targets of tests/fuzz (issue 15): builds them with clang into build-fuzz and runs each
# for SECONDS (default 30) on a copy of its seed corpus (tests/fuzz/corpus/NAME), ASan + UBSan on,
# 2 GiB RSS limit per target. A crash, leak, sanitizer report or memory blow-up fails the script and
# leaves the input in build-fuzz/artifacts/NAME/. Run it for 600 s or more to fuzz in earnest.
# CUBEAO_FUZZ_RUNS=N replaces the time limit by N inputs from a fixed seed, so a run is repeatable:
# CI replays the corpus (regressions of everything found so far included) and fuzzes that way.
# Usage: bash tools/fuzz.sh [SECONDS] [TARGET...]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-30}
shift || true
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(cache_reader camera_path ranges probe_set mesh viewer_script)
bash tools/install-deps.sh
CC=clang CXX=clang++ cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCUBEAO_FUZZ=ON >/dev/null
cmake --build build-fuzz -j2 --target $(printf 'fuzz_%s ' "${targets[@]}") >/dev/null
limit=(-max_total_time="$seconds")
[ -n "${CUBEAO_FUZZ_RUNS:-}" ] && limit=(-runs="$CUBEAO_FUZZ_RUNS" -seed=1)
for t in "${targets[@]}"; do
  work=build-fuzz/corpus/$t
  artifacts=build-fuzz/artifacts/$t
  mkdir -p "$work" "$artifacts"
  cp -n tests/fuzz/corpus/"$t"/* "$work"/ 2>/dev/null || true
  echo "fuzz: $t (${limit[*]})"
  ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:intercept_tls_get_addr=0 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    "build-fuzz/tests/fuzz/fuzz_$t" "$work" "${limit[@]}" -rss_limit_mb=2048 -timeout=20 \
    -artifact_prefix="$artifacts/" -print_final_stats=1 >"build-fuzz/fuzz_$t.log" 2>&1 ||
    { tail -40 "build-fuzz/fuzz_$t.log"; echo "fuzz: $t FAILED (input in $artifacts/)" >&2; exit 1; }
  grep -a -E "stat::number_of_executed_units|stat::peak_rss_mb" "build-fuzz/fuzz_$t.log" | tr '\n' ' '
  echo "corpus $(ls "$work" | wc -l)"
done
