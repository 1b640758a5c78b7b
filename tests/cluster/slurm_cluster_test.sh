#!/usr/bin/env bash
# A real Slurm cluster on localhost (slurmctld + slurmd, started and stopped here) runs the
# quick-start job as a 4-task array plus a merge job with the templates in docker/slurm/: the
# merged output must be byte-identical to a single-process run. Then an array with a failing task:
# the array fails, the merge job never runs, and `olt merge` refuses naming the shard.
#   bash tests/cluster/slurm_cluster_test.sh OLT_BINARY SOURCE_DIR
# Exits 77 (ctest: skipped) when Slurm is not installed.
set -euo pipefail
olt=$(realpath "$1")
src=$(realpath "$2")
for tool in slurmctld slurmd sbatch sinfo squeue scancel; do
  if ! command -v "$tool" > /dev/null; then
    echo "skipped: $tool not found (apt-get install slurmctld slurmd slurm-client)"
    exit 77
  fi
done

work=$(mktemp -d /tmp/olt-slurm-XXXXXX)
pids=()
cleanup() {
  set +e
  [ -n "${SLURM_CONF:-}" ] && scancel --quiet --user=root > /dev/null 2>&1
  sleep 0.5
  for pid in "${pids[@]}"; do kill -TERM "$pid" 2> /dev/null; done
  # An exited daemon may stay a zombie for a while: wait on the process state, not kill -0.
  for _ in $(seq 100); do
    alive=0
    for pid in "${pids[@]}"; do
      state=$(awk '{print $3}' "/proc/$pid/stat" 2> /dev/null || echo X)
      [ "$state" != X ] && [ "$state" != Z ] && alive=1
    done
    [ $alive = 0 ] && break
    sleep 0.1
  done
  for pid in "${pids[@]}"; do kill -KILL "$pid" 2> /dev/null; done
  rm -rf "$work"
}
trap cleanup EXIT
fail() {
  echo "FAILED: $*"
  for f in "$work"/*.log "$work"/run*/olt-*.log; do [ -f "$f" ] && { echo "--- $f"; tail -20 "$f"; }; done
  exit 1
}

# Two free loopback ports for the daemons.
read -r ctld_port slurmd_port < <(/usr/bin/python3 -c '
import socket
s = [socket.socket() for _ in range(2)]
for x in s: x.bind(("127.0.0.1", 0))
print(*[x.getsockname()[1] for x in s])')
node=$(slurmd -C | head -1 | sed -E 's/^NodeName=[^ ]+ //; s/ UpTime=.*//')
mkdir -p "$work/state" "$work/spool"
cat > "$work/slurm.conf" << CONF
ClusterName=olttest
SlurmctldHost=localhost(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
AuthType=auth/none
CredType=cred/none
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/filetxt
JobCompLoc=$work/jobcomp.txt
SchedulerType=sched/backfill
# Every second rather than slurmctld's default minute: the merge waits on its dependency for that long.
SchedulerParameters=sched_interval=1,bf_interval=1
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/slurmctld.log
SlurmdLogFile=$work/slurmd.log
SlurmUser=root
SlurmdUser=root
ReturnToService=2
MpiDefault=none
NodeName=localnode NodeAddr=127.0.0.1 NodeHostname=localhost $node
PartitionName=test Nodes=localnode Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF="$work/slurm.conf"
setsid slurmctld -D -f "$SLURM_CONF" > "$work/slurmctld.out" 2>&1 &
pids+=($!)
setsid slurmd -D -N localnode -f "$SLURM_CONF" > "$work/slurmd.out" 2>&1 &
pids+=($!)
for i in $(seq 150); do
  [ "$(sinfo -h -n localnode -o %t 2> /dev/null)" = idle ] && break
  [ "$i" = 150 ] && fail "the node did not become idle in 30 s"
  sleep 0.2
done
echo "slurm up: controller on 127.0.0.1:$ctld_port, node on :$slurmd_port"

# The quick-start job, with its output and a shared cache in a run folder of its own.
job_for() {  # RUN_DIR CACHE_DIR
  mkdir -p "$1"
  sed -E "s#^output:.*#output: out\ncache: $2#" "$src/jobs/quickstart.yaml" > "$1/job.yaml"
}

# Reference: one process, its own cache.
job_for "$work/run" "$work/cache-plain"
"$olt" run "$work/run/job.yaml" > "$work/plain.log" 2>&1 || fail "plain run"
mv "$work/run/out" "$work/expected"
job_for "$work/run" "$work/cache-shared"

start=$SECONDS
cd "$work/run"
array=$(OLT="$olt" sbatch --parsable --array=0-3 "$src/docker/slurm/olt-shards.sbatch" "$work/run/job.yaml")
OLT="$olt" sbatch --parsable --wait --dependency=afterok:"$array" --kill-on-invalid-dep=yes \
  "$src/docker/slurm/olt-merge.sbatch" "$work/run/job.yaml" > /dev/null || fail "the merge job failed"
elapsed=$((SECONDS - start))
for i in 0 1 2 3; do
  grep -q "shard $i/4 finished" "$work/run/olt-shard-${array}_$i.log" || fail "task $i did not run shard $i/4"
done
diff -r "$work/expected" "$work/run/out" > "$work/diff.txt" || fail "merged output differs: $(head -5 "$work/diff.txt")"
echo "ok: 4-task array + merge on Slurm: output byte-identical to one process ($(find "$work/run/out" -type f | wc -l) files, ${elapsed} s from submission to merged)"

# A failing task: the array fails, the merge job is never run, and olt merge refuses.
job_for "$work/failing" "$work/cache-failing"
cat > "$work/failing/olt" << WRAP
#!/usr/bin/env bash
if [ "\${SLURM_ARRAY_TASK_ID:-}" = 2 ]; then echo "deliberate failure of task 2" >&2; exit 1; fi
exec "$olt" "\$@"
WRAP
chmod +x "$work/failing/olt"
cd "$work/failing"
array=$(OLT="$work/failing/olt" sbatch --parsable --array=0-3 "$src/docker/slurm/olt-shards.sbatch" "$work/failing/job.yaml")
merge=$(OLT="$olt" sbatch --parsable --dependency=afterok:"$array" --kill-on-invalid-dep=yes \
  "$src/docker/slurm/olt-merge.sbatch" "$work/failing/job.yaml")
for i in $(seq 600); do
  [ -z "$(squeue -h -j "$array,$merge" 2> /dev/null)" ] && break
  [ "$i" = 600 ] && fail "jobs still queued after 120 s"
  sleep 0.2
done
grep "ArrayJobId=$array ArrayTaskId=2 " "$work/jobcomp.txt" | grep -q "JobState=FAILED" \
  || fail "task 2 is not recorded as failed: $(grep "ArrayJobId=$array" "$work/jobcomp.txt")"
[ "$(grep "ArrayJobId=$array " "$work/jobcomp.txt" | grep -c "JobState=COMPLETED")" = 3 ] \
  || fail "the other three tasks did not complete"
grep "JobId=$merge " "$work/jobcomp.txt" | grep -q "JobState=CANCELLED" || fail "the merge job was not cancelled"
[ -f "$work/failing/olt-merge-$merge.log" ] && fail "the merge job ran although a shard failed"
[ -e "$work/failing/out/manifest.json" ] && fail "output published although a shard failed"
set +e
"$olt" merge "$work/failing/job.yaml" > "$work/merge-refused.log" 2>&1
code=$?
set -e
[ "$code" = 3 ] || fail "olt merge exited $code, expected 3: $(cat "$work/merge-refused.log")"
grep -q "shard 2/4 of .* has not finished" "$work/merge-refused.log" || fail "olt merge did not name shard 2/4: $(cat "$work/merge-refused.log")"
echo "ok: a failing task fails the array; the merge job did not run; olt merge exits 3 naming shard 2/4"
echo "1 passed, 0 failed"
