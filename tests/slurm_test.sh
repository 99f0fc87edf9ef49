#!/bin/bash
# Slurm.ArrayBakeMatchesOneProcess (tests/CMakeLists.txt): tools/slurm/ on a real Slurm, a private
# one-node cluster on localhost in a temporary directory (own munged socket and key, own slurm.conf, own
# ports, state and logs), so a Slurm or munge already on the machine is not disturbed.
#   tests/slurm_test.sh CUBEAO_BINARY
# A 4-task array bake through tools/slurm/submit.sh --wait must give the cache a one-process bake writes,
# byte for byte, although shard 2's first attempt fails (retried in bake-shard.sbatch); the merge job must
# refuse the set without shard 2, naming it. Prints "SKIP: reason" (the test's skip regex) without slurm or
# munge, as non-root, or when the daemons do not come up.
set -euo pipefail

real_cubeao=$(realpath "${1:?usage: slurm_test.sh CUBEAO_BINARY}")
repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
start=$SECONDS

skip() { echo "SKIP: $*"; exit 0; }
fail() { echo "FAIL: $*" >&2; exit 1; }

for tool in munged slurmctld slurmd sbatch sinfo scontrol squeue scancel; do
    command -v "$tool" >/dev/null || skip "$tool not installed (tools/install-deps.sh installs slurm-wlm and munge)"
done
[ "$(id -u)" -eq 0 ] || skip "needs root (slurmd runs jobs as their user; this cluster runs as root)"

tmp=$(mktemp -d /tmp/cubeao-slurm.XXXXXX)
chmod 700 "$tmp"
pids=()
jobs_submitted=()
cleanup() {
    set +e
    for j in "${jobs_submitted[@]}"; do timeout 5 scancel "$j" 2>/dev/null; done
    # Daemons in reverse order of start, by the pids we started.
    for ((k = ${#pids[@]} - 1; k >= 0; --k)); do kill "${pids[k]}" 2>/dev/null; done
    for p in "${pids[@]}"; do
        for _ in $(seq 50); do kill -0 "$p" 2>/dev/null || break; sleep 0.1; done
        kill -9 "$p" 2>/dev/null
    done
    rm -rf "$tmp"
}
trap cleanup EXIT

show_logs() {
    local f
    for f in "$tmp"/log/*; do
        if [ -s "$f" ]; then echo "--- $f"; tail -n 15 "$f"; fi
    done
}

# Two free TCP ports for slurmctld and slurmd.
read -r ctld_port slurmd_port < <(python3 - <<'PY'
import socket
socks = [socket.socket() for _ in range(2)]
for s in socks: s.bind(("127.0.0.1", 0))
print(*(s.getsockname()[1] for s in socks))
PY
)

mkdir -p "$tmp"/{munge,state,spool,log,run}
chmod 700 "$tmp"/munge
dd if=/dev/urandom of="$tmp/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$tmp/munge/munge.key"
socket="$tmp/munge/munge.socket"
munged --foreground --force --socket="$socket" --key-file="$tmp/munge/munge.key" --pid-file="$tmp/run/munged.pid" \
    --log-file="$tmp/log/munged.log" --seed-file="$tmp/munge/munged.seed" >"$tmp/log/munged.out" 2>&1 &
pids+=($!)

host=$(hostname -s)
node=$(slurmd -C | head -1 | sed 's/ UpTime=.*//')  # NodeName=host CPUs=... RealMemory=..., as slurmd sees it
cpus=$(sed -n 's/.* CPUs=\([0-9]*\).*/\1/p' <<<"$node")
export SLURM_CONF="$tmp/slurm.conf"
cat >"$SLURM_CONF" <<CONF
ClusterName=cubeaotest
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$socket
MpiDefault=none
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
StateSaveLocation=$tmp/state
SlurmdSpoolDir=$tmp/spool
SlurmctldPidFile=$tmp/run/slurmctld.pid
SlurmdPidFile=$tmp/run/slurmd.pid
SlurmctldLogFile=$tmp/log/slurmctld.log
SlurmdLogFile=$tmp/log/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
$node NodeAddr=127.0.0.1 State=UNKNOWN
PartitionName=cubeao Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF

for _ in $(seq 50); do [ -S "$socket" ] && break; sleep 0.1; done
[ -S "$socket" ] || { show_logs; skip "munged did not start"; }
slurmctld -D -c -f "$SLURM_CONF" >"$tmp/log/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D -f "$SLURM_CONF" >"$tmp/log/slurmd.out" 2>&1 &
pids+=($!)
# By the clock: a client's call to a controller that is not there can itself take seconds (its retries).
up=0 deadline=$((SECONDS + 30))
while [ $SECONDS -lt $deadline ]; do
    if [ "$(timeout 5 sinfo -h -n "$host" -o %t 2>/dev/null)" = idle ]; then up=1; break; fi
    sleep 0.5
done
if [ $up -eq 0 ]; then
    { timeout 5 sinfo 2>&1 || true; } | tail -n 5
    show_logs
    skip "the private Slurm did not come up within 30 s (logs above)"
fi
echo "slurm: node $host ($cpus CPUs) idle after $((SECONDS - start)) s; ports $ctld_port, $slurmd_port"

# The probes and the one-process reference bake.
bake_args=(--res 16 --spp 8)  # and --device cpu: the same on every machine, and no GL needed
probes="$tmp/probes.json"
"$real_cubeao" place builtin:box-room --method grid --budget 8 --out "$probes" >/dev/null
count=$(python3 -c 'import json,sys; print(len(json.load(open(sys.argv[1]))["probes"]))' "$probes")
[ "$count" -ge 4 ] || fail "place wrote $count probes, want at least 4 (one per shard)"
"$real_cubeao" bake builtin:box-room --probes "$probes" --out "$tmp/one.cubeao" --device cpu "${bake_args[@]}" \
    >/dev/null

# $CUBEAO for the jobs: fails shard 2's first attempt, once (the marker file), then is the real binary.
cat >"$tmp/flaky-cubeao" <<WRAP
#!/bin/bash
if [[ " \$* " == *" --shard 2/4 "* ]] && [ ! -e "$tmp/shard2-failed-once" ]; then
    touch "$tmp/shard2-failed-once"
    echo "flaky-cubeao: failing the first attempt of shard 2/4" >&2
    exit 3
fi
exec "$real_cubeao" "\$@"
WRAP
chmod +x "$tmp/flaky-cubeao"

mkdir -p "$tmp/out"
out="$tmp/out/box.cubeao"
set +e
submitted=$(CUBEAO="$tmp/flaky-cubeao" CUBEAO_RETRY_DELAY=0 "$repo/tools/slurm/submit.sh" builtin:box-room "$probes" \
    "$out" --shards 4 --device cpu --retries 2 --wait -- "${bake_args[@]}" 2>&1)
rc=$?
set -e
echo "$submitted"
for j in $(sed -n 's/.*bake job \([0-9]*\).*merge job \([0-9]*\)$/\1 \2/p' <<<"$submitted"); do
    jobs_submitted+=("$j")
done
shard_dir="$out.shards"
if [ $rc -ne 0 ]; then
    for f in "$shard_dir"/*.log; do echo "--- $f"; tail -n 20 "$f"; done
    show_logs
    fail "submit.sh --wait exited $rc"
fi
[ -e "$tmp/shard2-failed-once" ] || fail "the flaky wrapper never failed shard 2: retries not exercised"
grep -q "attempt 1 of task 2/4 failed" "$shard_dir/bake_2.log" || fail "bake_2.log does not show the retry"
grep -q "task 2/4 done after 2 attempt" "$shard_dir/bake_2.log" || fail "shard 2 did not succeed on its retry"
cmp "$out" "$tmp/one.cubeao" || fail "the merged array bake differs from the one-process bake"
echo "ok: 4-task array bake (shard 2 retried) merged byte-identical to the one-process bake ($count probes)"

# Without shard 2 the merge job refuses, naming it, and writes nothing.
mv "$shard_dir/shard_2.cubeao" "$tmp/shard_2.cubeao"
merge_job=$(CUBEAO="$real_cubeao" sbatch --parsable --output "$tmp/refused.log" "$repo/tools/slurm/merge.sbatch" \
    "$tmp/out/refused.cubeao" "$shard_dir" "$probes" 4)
merge_job=${merge_job%%;*}
jobs_submitted+=("$merge_job")
# Polled here rather than with sbatch --wait, whose first polls are seconds apart.
for _ in $(seq 300); do
    state=$(scontrol -o show job "$merge_job" | sed -n 's/.*JobState=\([A-Z_]*\).*/\1/p')
    case "$state" in PENDING | CONFIGURING | RUNNING | COMPLETING) sleep 0.1 ;; *) break ;; esac
done
cat "$tmp/refused.log"
[ "$state" = FAILED ] || fail "merge job of 3 of 4 shards: $state, want FAILED"
grep -Eq "incomplete: [0-9]+ of $count probes missing: 2([, ]|$).*\(shard 2/4\)" "$tmp/refused.log" ||
    fail "the refusal does not name probe 2 and shard 2/4"
[ ! -e "$tmp/out/refused.cubeao" ] || fail "the refused merge wrote its output"
echo "ok: merge without shard 2 refused, naming shard 2/4 ($((SECONDS - start)) s in all)"
