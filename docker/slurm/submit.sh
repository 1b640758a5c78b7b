#!/usr/bin/env bash
# Submits an OLT job to Slurm as an array of N shards plus a merge that runs only if every shard
# succeeded. Prints the two job ids. Extra sbatch options (partition, account, time) go in
# SBATCH_* environment variables or after `--`.
#   bash docker/slurm/submit.sh JOB.yaml N [-- SBATCH_OPTIONS...]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
job=$(realpath "${1:?usage: submit.sh JOB.yaml N [-- SBATCH_OPTIONS...]}")
shards=${2:?usage: submit.sh JOB.yaml N [-- SBATCH_OPTIONS...]}
shift 2
[ "${1:-}" = "--" ] && shift
array=$(sbatch --parsable --array=0-$((shards - 1)) "$@" "$here/olt-shards.sbatch" "$job")
merge=$(sbatch --parsable --dependency=afterok:"$array" --kill-on-invalid-dep=yes "$@" "$here/olt-merge.sbatch" "$job")
echo "shards: $array (array of $shards)  merge: $merge"
