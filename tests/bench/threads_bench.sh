#!/usr/bin/env bash
# Threads on a busy machine: every stage of the shipped jobs, run from a fresh cache with the
# default thread count and with one thread, side by side in this one script, idle and then with
# COMPETITORS CPU-bound processes (default 6) sharing the cores, as on a shared workstation or an
# oversubscribed cluster node. Each job runs REPEATS times (default 3) with each thread count, in
# turn (the order swapped every repeat, so neither always runs first). Prints one row per stage: the
# median seconds with the default threads and with one thread, their ratio (default / one: below 1
# the threads help; the goal is never above 1), and the range of the repeats' own ratios. Stages
# that run side by side (jobs.md) share the cores with the threads as they are, one after the other
# with one: their rows are each one's time beside the other, and the job's row `(whole_run)` is the
# figure to compare there.
#   [REPEATS=N] [COMPETITORS=N] bash tests/bench/threads_bench.sh build/olt [JOB ...]
#   (default: every job of jobs/)
set -euo pipefail
export LC_ALL=C  # numbers with a decimal point for sort -g and awk, and one collation for sort and join
olt=$(realpath "$1")
shift
repo=$(cd "$(dirname "$0")/../.." && pwd)
competitors=${COMPETITORS:-6}
repeats=${REPEATS:-3}
jobs=("$@")
[ ${#jobs[@]} -gt 0 ] || jobs=("$repo"/jobs/*.yaml)
work=$(mktemp -d)
source "$(dirname "$0")/competitors.sh"
trap 'stop_load; rm -rf "$work"' EXIT
mkdir -p "$work/repo"
cp -r "$repo/jobs" "$work/repo/jobs"
ln -s "$repo/../shared" "$work/shared"

# stage -> seconds of one run ("[3/8] labels (propagate): done in 1.05 s: ..."), and the whole run's
stage_times() {
  sed -nE 's/.*\] ([^ ]+) \(([a-z_]+)\): done in ([0-9.]+) s.*/\1 \3/p' "$1"
  cat "$1.seconds"
}

run() {  # run NAME THREADS LOG: a fresh cache, the job's output removed; the run's seconds in LOG.seconds
  local name=$1 threads=$2 log=$3 start
  rm -rf "$work/cache"
  start=$(date +%s.%N)
  run_once "$name" "$threads" "$log" || return 1
  awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { printf "(whole_run) %.3f\n", b - a }' > "$log.seconds"
}

run_once() {
  local name=$1 threads=$2 log=$3
  if [ "$threads" = default ]; then
    OLT_CACHE_DIR="$work/cache" "$olt" run "$work/repo/jobs/$name.yaml" > "$log" 2>&1
  else
    # OMP_NUM_THREADS: the same for olt versions before oneTBB, to compare with them.
    OLT_THREADS=$threads OMP_NUM_THREADS=$threads OLT_CACHE_DIR="$work/cache" "$olt" run "$work/repo/jobs/$name.yaml" > "$log" 2>&1
  fi
}

# STAGE SECONDS lines of every repeat -> STAGE MEDIAN per stage
medians() {
  sort -k1,1 -k2,2g "$1" | awk '{ t[$1] = t[$1] " " $2 } END {
    for (s in t) { n = split(substr(t[s], 2), v, " "); m = n % 2 ? v[(n + 1) / 2] : (v[n / 2] + v[n / 2 + 1]) / 2
                   printf "%s %.3f\n", s, m } }' | sort
}

# STAGE RATIO lines of every repeat -> STAGE LOWEST-HIGHEST per stage
ranges() {
  sort -k1,1 -k2,2g "$1" | awk '{ if (!($1 in lo)) lo[$1] = $2; hi[$1] = $2 } END {
    for (s in lo) printf "%s %.2f-%.2f\n", s, lo[s], hi[s] }' | sort
}

printf '%-26s %-22s %8s %10s %10s %7s %12s\n' job stage load default "1 thread" ratio "per repeat"
for condition in idle busy; do
  if [ "$condition" = busy ]; then start_load "$competitors"; fi
  for job in "${jobs[@]}"; do
    name=$(basename "$job" .yaml)
    data=$(grep -o '\.\./\.\./shared/data/[A-Za-z0-9_]*' "$job" | head -1 | sed 's#\.\./\.\./shared/data/##' || true)
    if [ -n "$data" ] && [ ! -d "$repo/../shared/data/$data" ]; then
      echo "$name: ../shared/data/$data is absent, skipped"
      continue
    fi
    : > "$work/default.times"
    : > "$work/one.times"
    : > "$work/ratios"
    failed=
    for r in $(seq "$repeats"); do
      order="default 1"
      [ $((r % 2)) -eq 0 ] && order="1 default"
      for threads in $order; do
        run "$name" "$threads" "$work/$threads.log" || { failed=$threads; break 2; }
      done
      stage_times "$work/default.log" >> "$work/default.times"
      stage_times "$work/1.log" >> "$work/one.times"
      join <(stage_times "$work/default.log" | sort) <(stage_times "$work/1.log" | sort) |
        awk '$3 > 0 { printf "%s %.6f\n", $1, $2 / $3 }' >> "$work/ratios"
    done
    if [ -n "$failed" ]; then
      echo "$name failed ($failed threads):"
      tail -3 "$work/$failed.log"
      continue
    fi
    join <(medians "$work/default.times") <(medians "$work/one.times") | join - <(ranges "$work/ratios") |
      while read -r stage many one range; do
        # Stages of a few milliseconds say nothing about threads.
        awk -v a="$many" -v b="$one" 'BEGIN { exit !(a < 0.02 && b < 0.02) }' && continue
        ratio=$(awk -v a="$many" -v b="$one" 'BEGIN { if (b > 0) printf "%.2f", a / b; else print "-" }')
        printf '%-26s %-22s %8s %10s %10s %7s %12s\n' "$name" "$stage" "$condition" "$many" "$one" "$ratio" "$range"
      done
  done
  stop_load
done
