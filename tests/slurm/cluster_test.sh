#!/usr/bin/env bash
# make test-slurm: a real one-node Slurm cluster on the loopback address (Debian's slurm-wlm and
# munge; configuration, state, logs and sockets in a temporary folder; every daemon started here
# and stopped on exit), on which scripts/slurm/glint-farm renders scenes/cornell in 4 shards
# (shard 2 made to fail once, so that Slurm requeues it alone), merges them again as a tree
# (--merge-fan-in 2) and builds a bank in 2 parts. The
# merged frame must equal a single-machine render of the same seed and spp, and the bank folder
# a single-machine bank: the same index.json, byte for byte, and members with the same pixels
# (docs/distributed.md).
# Usage: tests/slurm/cluster_test.sh BUILD_DIR
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
bin="$(cd "${1:-build}" && pwd)/bin"
for b in glint-render glint-image glint-denoise; do
  [ -x "$bin/$b" ] || { echo "cluster_test: $bin/$b not built" >&2; exit 2; }
done
for d in munged slurmctld slurmd sbatch; do
  command -v "$d" >/dev/null || { echo "cluster_test: $d missing (apt-get install slurm-wlm munge)" >&2; exit 2; }
done
start=$(date +%s.%N)
T="$(mktemp -d /tmp/glint-slurm.XXXXXX)"
pids=()
cleanup() {
  local rc=$?
  for ((k = ${#pids[@]} - 1; k >= 0; k--)); do kill "${pids[k]}" 2>/dev/null || true; done
  for p in "${pids[@]}"; do
    for _ in $(seq 50); do kill -0 "$p" 2>/dev/null || break; sleep 0.1; done
    kill -9 "$p" 2>/dev/null || true
  done
  if [ $rc -ne 0 ]; then
    echo "cluster_test: FAILED; daemon logs:" >&2
    tail -n 20 "$T"/*.log >&2 2>/dev/null || true
  fi
  rm -rf "$T"
  exit $rc
}
trap cleanup EXIT INT TERM

free_port() { python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'; }
host="$(hostname -s)"
ctld_port=$(free_port); slurmd_port=$(free_port)
while [ "$slurmd_port" = "$ctld_port" ]; do slurmd_port=$(free_port); done

# munge: a fresh key, its own socket.
mkdir -p "$T/munge" "$T/state" "$T/spool" "$T/work"
chmod 700 "$T/munge"
dd if=/dev/urandom of="$T/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$T/munge/munge.key"
munged --foreground --force --socket="$T/munge/munge.socket" --key-file="$T/munge/munge.key" \
  --pid-file="$T/munge/munged.pid" --seed-file="$T/munge/munged.seed" \
  --log-file="$T/munged.log" >"$T/munged.out" 2>&1 &
pids+=($!)
for _ in $(seq 50); do [ -S "$T/munge/munge.socket" ] && break; sleep 0.1; done
[ -S "$T/munge/munge.socket" ] || { echo "cluster_test: munged did not start" >&2; exit 1; }

cat >"$T/slurm.conf" <<CONF
ClusterName=glinttest
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$T/munge/munge.socket,cred_expire=5
CredType=cred/munge
StateSaveLocation=$T/state
SlurmdSpoolDir=$T/spool
SlurmctldPidFile=$T/slurmctld.pid
SlurmdPidFile=$T/slurmd.pid
SlurmctldLogFile=$T/slurmctld.log
SlurmdLogFile=$T/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
SwitchType=switch/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
MinJobAge=600
SchedulerParameters=defer_batch,sched_interval=1
MailProg=/bin/true
PlugStackConfig=$T/plugstack.conf
NodeName=glint-node NodeHostname=$host NodeAddr=127.0.0.1 CPUs=$(nproc) State=UNKNOWN
PartitionName=glint Nodes=glint-node Default=YES MaxTime=60 State=UP
CONF
: >"$T/plugstack.conf"
export SLURM_CONF="$T/slurm.conf"
slurmctld -D -i -f "$SLURM_CONF" >"$T/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D -f "$SLURM_CONF" -N glint-node >"$T/slurmd.out" 2>&1 &
pids+=($!)
for _ in $(seq 100); do
  state=$(sinfo -h -n glint-node -o %t 2>/dev/null || true)
  [ "$state" = idle ] && break
  sleep 0.2
done
[ "$state" = idle ] || { echo "cluster_test: node not idle ($state)" >&2; exit 1; }
up=$(date +%s.%N)
echo "cluster_test: cluster up in $(python3 -c "print(round($up - $start, 1))") s"

export GLINT_BIN="$bin"
scene="$root/scenes/cornell/scene.json"
W="$T/work"

# 1. A 4-shard render (shard 2 fails its first attempt and is requeued by itself), merged.
t0=$(date +%s.%N)
GLINT_FARM_FAIL_ONCE=2 "$root/scripts/slurm/glint-farm" render "$scene" --spp 16 --seed 9 \
  --shards 4 --out "$W/full.exr" --work "$W/shards" --retries 1 \
  --partition glint --time 5 --cpus-per-task 1 --wait
t1=$(date +%s.%N)
"$bin/glint-render" "$scene" --spp 16 --seed 9 --out "$W/single.exr" >/dev/null 2>&1
mse=$("$bin/glint-image" diff "$W/full.exr" --reference "$W/single.exr" --metric mse --json |
  python3 -c 'import json,sys; print(json.load(sys.stdin)["value"])')
python3 - "$mse" <<'PY'
import sys
mse = float(sys.argv[1])
# Float rounding of a mean near 1 is ~6e-8; its square is ~4e-15.
assert mse < 1e-12, f"merged frame differs from the single render: mse {mse}"
print(f"cluster_test: merged 4 shards = single render (mse {mse:.3g} < 1e-12)")
PY
attempts() { grep -c "attempt" "$W/shards/shard-$1.log"; }
[ "$(attempts 2)" -ge 2 ] || { echo "cluster_test: shard 2 was not requeued" >&2; exit 1; }
for i in 0 1 3; do
  [ "$(attempts $i)" = 1 ] || { echo "cluster_test: shard $i ran $(attempts $i) times" >&2; exit 1; }
done
echo "cluster_test: shard 2 failed once and was rerun alone ($(attempts 2) attempts; shards 0, 1, 3 ran once)"

# 1b. The same render merged as a tree (--merge-fan-in 2: partial merges of shards 0-1 and 2-3,
# then their merge). The shard files are there, so the render tasks exit at once.
t4=$(date +%s.%N)
"$root/scripts/slurm/glint-farm" render "$scene" --spp 16 --seed 9 --shards 4 --merge-fan-in 2 \
  --out "$W/tree.exr" --work "$W/shards" --partition glint --time 5 --cpus-per-task 1 --wait
t5=$(date +%s.%N)
for g in 0 1; do
  "$bin/glint-image" info --json "$W/shards/part-$g-of-2.exr" | python3 -c '
import json, sys
shard = json.load(sys.stdin)["metadata"]["extra"]["shard"]
assert shard == sys.argv[1], f"part {sys.argv[2]} holds {shard}, expected {sys.argv[1]}"' \
    "$((2 * g))-$((2 * g + 1))/4" "$g"
done
tree_mse=$("$bin/glint-image" diff "$W/tree.exr" --reference "$W/full.exr" --metric mse --json |
  python3 -c 'import json,sys; print(json.load(sys.stdin)["value"])')
python3 - "$tree_mse" <<'PY'
import sys
mse = float(sys.argv[1])
# Tree and flat merge differ by float rounding only (docs/distributed.md, "Tree merge").
assert mse < 1e-12, f"tree merge differs from the flat merge: mse {mse}"
print(f"cluster_test: tree merge (fan-in 2: parts 0-1/4, 2-3/4) = flat merge (mse {mse:.3g} < 1e-12)")
PY

# 2. A bank in 2 parts into one folder, against one machine's bank.
t2=$(date +%s.%N)
"$root/scripts/slurm/glint-farm" bank "$W/single.exr" --size 8 --seed 4 --parts 2 \
  --filters gaussian,bilateral,cross-bilateral --out "$W/bank" --partition glint --time 5 --wait
t3=$(date +%s.%N)
"$bin/glint-denoise" bank "$W/single.exr" --size 8 --seed 4 --filters gaussian,bilateral,cross-bilateral \
  --out "$W/bank-single" >/dev/null
# index.json names every member with its key and pixel checksum; the member files must also
# hold the same pixels (their bytes differ only in the EXR's capDate).
cmp "$W/bank-single/index.json" "$W/bank/index.json"
members=0
for f in "$W/bank-single"/m-*.exr; do
  mse=$("$bin/glint-image" diff "$W/bank/$(basename "$f")" --reference "$f" --metric mse --json |
    python3 -c 'import json,sys; print(json.load(sys.stdin)["value"])')
  [ "$mse" = "0.0" ] || { echo "cluster_test: $(basename "$f") differs (mse $mse)" >&2; exit 1; }
  members=$((members + 1))
done
[ "$(ls "$W/bank" | grep -c '^m-')" = "$members" ] || { echo "cluster_test: member files differ in number" >&2; exit 1; }
[ -z "$(ls "$W/bank" | grep '^index.members-' || true)" ] || { echo "cluster_test: partial indices left" >&2; exit 1; }
echo "cluster_test: 2-part bank = single-machine bank (index.json identical, $members member files with identical pixels)"
end=$(date +%s.%N)
python3 -c "print(f'cluster_test: passed in {$end - $start:.1f} s (cluster start {$up - $start:.1f} s, render jobs {$t1 - $t0:.1f} s, tree merge jobs {$t5 - $t4:.1f} s, bank jobs {$t3 - $t2:.1f} s)')"
