#!/bin/bash
# Bakes a probe set on a Slurm cluster (tools/slurm/README.md): an array of N `cubeao bake --shard I/N`
# tasks (bake-shard.sbatch), then a merge that runs when all of them have ended (merge.sbatch) and refuses
# an incomplete set, naming the missing shards.
#   submit.sh SCENE PROBES OUT --shards N [--partition P] [--device auto|gpu|cpu] [--retries K] [--wait]
#             [-- extra bake args]
# Writes OUT (the merged cache) and, beside it, OUT's name + ".shards/": shard_I.cubeao, bake_I.log,
# merge.log. Prints the two job ids; with --wait, blocks until the merge has ended and exits with its
# status. Running the same command again resumes: every shard skips the probes it already holds.
# The binary: $CUBEAO (default `cubeao` on PATH), as the jobs see it (sbatch passes the environment).
# Other sbatch settings through sbatch's own environment variables (SBATCH_ACCOUNT, SBATCH_TIMELIMIT...).
set -euo pipefail

usage() {
    echo "usage: submit.sh SCENE PROBES OUT --shards N [--partition P] [--device auto|gpu|cpu] [--retries K]" \
         "[--wait] [-- extra bake args]" >&2
    exit 2
}
die() { echo "submit: $*" >&2; exit 2; }

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
positional=() shards="" partition="" device=auto retries=2 wait=0 extra=()
while [ $# -gt 0 ]; do
    case "$1" in
        --shards) shards=${2:?--shards needs N}; shift 2 ;;
        --partition) partition=${2:?--partition needs a name}; shift 2 ;;
        --device) device=${2:?--device needs auto, gpu or cpu}; shift 2 ;;
        --retries) retries=${2:?--retries needs K}; shift 2 ;;
        --wait) wait=1; shift ;;
        --) shift; extra=("$@"); break ;;
        -h | --help) usage ;;
        -*) die "unknown option $1" ;;
        *) positional+=("$1"); shift ;;
    esac
done
[ ${#positional[@]} -eq 3 ] || usage
[[ "$shards" =~ ^[1-9][0-9]*$ ]] || die "--shards N is required, N >= 1"
[[ "$retries" =~ ^[0-9]+$ ]] || die "--retries K: expected a count, got '$retries'"
case "$device" in auto | gpu | cpu) ;; *) die "--device $device: expected auto, gpu or cpu" ;; esac
for arg in "${extra[@]}"; do
    case "$arg" in
        --device | --device=* | --shard | --shard=* | --out | --out=* | --probes | --probes=*)
            die "extra bake args: ${arg%%=*} is set by submit.sh (use its own options)" ;;
    esac
done
command -v sbatch >/dev/null || die "sbatch not found: is this a Slurm submit host?"

# Absolute paths: the jobs may start in another directory (and on another node, on shared storage).
abspath() { case "$1" in /*) echo "$1" ;; *) echo "$PWD/$1" ;; esac; }
scene=${positional[0]}
[[ "$scene" == builtin:* ]] || scene=$(abspath "$scene")
probes=$(abspath "${positional[1]}")
out=$(abspath "${positional[2]}")
[ -f "$probes" ] || die "probes file $probes not found"
[ -d "$(dirname "$out")" ] || die "directory of $out not found"
shard_dir="$out.shards"
mkdir -p "$shard_dir"

# A GPU per task where there are GPUs: always for --device gpu; for auto when the partition's nodes have
# gpu gres (sinfo %G, e.g. "gpu:a100:4"); the task then sees it (SLURM_JOB_GPUS) and bakes on it.
sbatch_args=()
[ -n "$partition" ] && sbatch_args+=(--partition "$partition")
gres=""
if [ "$device" = gpu ]; then
    gres=yes
elif [ "$device" = auto ]; then
    if [ -n "$partition" ]; then
        gres_list=$(sinfo -h -p "$partition" -o %G 2>/dev/null || true)
    else  # the default partition is the one sinfo marks with '*'
        gres_list=$(sinfo -h -o '%P %G' 2>/dev/null | awk '$1 ~ /\*$/ {print $2}' || true)
    fi
    grep -q 'gpu' <<<"$gres_list" && gres=yes
fi

bake_args=("${sbatch_args[@]}" --array "0-$((shards - 1))" --output "$shard_dir/bake_%a.log")
[ -n "$gres" ] && bake_args+=(--gres gpu:1)
bake_job=$(sbatch --parsable "${bake_args[@]}" "$here/bake-shard.sbatch" \
    "$scene" "$probes" "$shard_dir" "$shards" "$device" "$retries" "${extra[@]}")
bake_job=${bake_job%%;*}  # "id;cluster" on multi-cluster setups
# afterany, not afterok: a failed shard must end in merge's refusal naming it, not in a merge job that
# waits forever on a dependency that can no longer be met.
merge_job=$(sbatch --parsable "${sbatch_args[@]}" --dependency "afterany:$bake_job" --output "$shard_dir/merge.log" \
    "$here/merge.sbatch" "$out" "$shard_dir" "$probes" "$shards")
merge_job=${merge_job%%;*}
echo "submit: bake job $bake_job (array 0-$((shards - 1)), device $device${gres:+, gres gpu:1}), merge job $merge_job"
echo "submit: shards and logs in $shard_dir; merged cache $out"
[ "$wait" -eq 1 ] || exit 0

# Poll the merge job every 2 s (one light RPC): scontrol while slurmctld still holds its record (MinJobAge,
# 300 s by default), sacct once it is gone.
state="" code=""
while :; do
    line=$(scontrol -o show job "$merge_job" 2>/dev/null || true)
    if [ -n "$line" ]; then
        state=$(sed -n 's/.*JobState=\([A-Z_]*\).*/\1/p' <<<"$line")
        code=$(sed -n 's/.* ExitCode=\([0-9]*\):\([0-9]*\).*/\1 \2/p' <<<"$line")
    else
        read -r state code < <(sacct -n -X -P -j "$merge_job" -o State,ExitCode 2>/dev/null |
            head -1 | sed 's/|/ /;s/:/ /') || true
        [ -n "$state" ] || die "merge job $merge_job: no record in scontrol or sacct"
    fi
    case "$state" in
        PENDING | RUNNING | CONFIGURING | COMPLETING | REQUEUED | REQUEUE_HOLD | REQUEUE_FED | RESIZING | SUSPENDED | \
            STAGE_OUT | SIGNALING | "") sleep 2 ;;
        *) break ;;
    esac
done
read -r status signal <<<"${code:-1 0}"
echo "submit: merge job $merge_job $state, exit $status; log $shard_dir/merge.log"
[ "$state" = COMPLETED ] && exit 0
[ "${status:-0}" -ne 0 ] && exit "$status"
exit 1
