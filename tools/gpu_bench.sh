#!/usr/bin/env bash
# The run time's figures on a GPU machine (issue 13: projection + blur <= 0.5 ms at 1080p with 2,000
# resident probes), in one device call. That machine has no packages and starts bare
# (../shared/gpu/README.md), so the small benchmark binary cubeao-gpubench (no Embree, no OIIO) travels
# with its libraries and the GL client packages:
#
#   here, once per build:     bash tools/gpu_bench.sh pack
#                             (builds cubeao-gpubench in build/, copies it and its libraries into
#                             .gpubench/, the GL client .debs into .gl/; both git-ignored, ~15 MB)
#   on the device machine:    the device tool's `run` with carry [".gl", ".gpubench"] and the command
#                             bash tools/gpu_bench.sh run
#                             (unpacks the GL packages, runs the configurations below, writes each
#                             one's table and JSON line to $OUT, or to out/gpu-bench without $OUT)
#   here, to try the run step on llvmpipe at a tiny size:
#                             CUBEAO_GPU_BENCH_TINY=1 bash tools/gpu_bench.sh run
#
# Record the figures with the GPU, driver and command in docs/BENCHMARKS.md.
set -euo pipefail
cd "$(dirname "$0")/.."

pack() {
    local shared=${CUBEAO_SHARED_DIR:-../shared}
    [ -x "$shared/gpu/pack_libs.sh" ] || [ -f "$shared/gpu/pack_libs.sh" ] ||
        { echo "gpu_bench.sh: $shared/gpu/pack_libs.sh not found (set CUBEAO_SHARED_DIR)" >&2; exit 1; }
    [ -d build ] || cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
    cmake --build build -j2 --target cubeao-gpubench
    rm -rf .gpubench && mkdir -p .gpubench
    cp build/cubeao-gpubench .gpubench/
    sh "$shared/gpu/pack_libs.sh" build/cubeao-gpubench .gpubench
    if ! ls .gl/*.deb >/dev/null 2>&1; then
        local lists
        lists=$(mktemp -d)
        mkdir -p "$lists/partial" .gl
        local o=(-oAPT::Architecture=amd64 -oAPT::Architectures=amd64 "-oDir::State::Lists=$lists")
        apt-get "${o[@]}" update >/dev/null
        (cd .gl && apt-get "${o[@]}" download libvulkan1 libegl1 libglvnd0 libopengl0 libgl1 libglx0 libgles2)
        rm -rf "$lists"
    fi
    echo "packed: $(du -sh .gpubench | cut -f1) in .gpubench, $(du -sh .gl | cut -f1) in .gl"
}

run() {
    local out=${OUT:-out/gpu-bench}
    mkdir -p "$out"
    # The GL client packages go into / only where the NVIDIA driver is (the device machine), never here.
    if ls .gl/*.deb >/dev/null 2>&1 && [ "$(id -u)" = 0 ] && [ -e /dev/nvidiactl ]; then
        for f in .gl/*.deb; do dpkg -x "$f" /; done
        ldconfig
    fi
    if [ -f /usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json ]; then
        export __EGL_VENDOR_LIBRARY_FILENAMES=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
    fi
    local bin=build/cubeao-gpubench
    if [ -x .gpubench/cubeao-gpubench ]; then
        bin=.gpubench/cubeao-gpubench
        export LD_LIBRARY_PATH=$PWD/.gpubench/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
    fi
    export CUBEAO_SHADER_DIR=$PWD/shaders CUBEAO_EGL_PLATFORM=${CUBEAO_EGL_PLATFORM:-device}
    { nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv 2>&1 || true; uname -a
      ldd --version 2>&1 | sed -n 1p; } > "$out/machine.txt"  # sed, not head: no SIGPIPE under pipefail
    cat "$out/machine.txt"

    # name | arguments. The first is the target; the rest place it: the issue's 10,000-probe budget
    # on a GPU, the measuring renderer's per-pass stalls against the frame loop.
    local size="--width 1920 --height 1080 --frames 300 --warmup 30"
    local probes=2000 many=10000 res=256
    if [ -n "${CUBEAO_GPU_BENCH_TINY:-}" ]; then
        size="--width 96 --height 54 --frames 3 --warmup 1"
        probes=20 many=60 res=16
    fi
    local configs=(
        "target|--probes $probes --res $res $size --methods probes,gtao"
        "budget20|--probes 20 --res $res $size --methods probes --gpu-budget-mb 256"
        "budget10k|--probes $many --res $res $size --methods probes --gpu-budget-mb 256"
        "wallclock|--probes $probes --res $res $size --methods probes,gtao --clock wall"
    )
    local status=0 c name args
    for c in "${configs[@]}"; do
        name=${c%%|*} args=${c#*|}
        echo "== $name: cubeao-gpubench $args --json" | tee "$out/$name.txt"
        if ! "$bin" $args --json >>"$out/$name.txt" 2>&1; then
            echo "   failed (see $out/$name.txt)"
            status=1
        fi
        grep -v '^{' "$out/$name.txt" | tail -n +2
        grep '^{' "$out/$name.txt" | tail -1 > "$out/$name.json" || true
    done
    return $status
}

case "${1:-}" in
    pack) pack ;;
    run) run ;;
    *) echo "usage: $0 pack|run" >&2; exit 2 ;;
esac
