#!/usr/bin/env bash
# Scale and start-up: a synthetic hand-held recording of 1,000 and of 10,000 observations (64x48
# pixels, to keep it quick) labeled end to end; per size the run's wall time and peak memory, then
# `olt plan`, `olt cache verify` and `olt cache gc` on its cache; and the time `olt run` takes when it
# has nothing to do (the median of 21, the quick start's job, cached). Ratios are 10,000 over 1,000,
# measured side by side in this one script.
#   bash tests/bench/scale_bench.sh build/olt [SMALL LARGE]
set -euo pipefail
olt=$(realpath "$1")
small=${2:-1000}
large=${3:-10000}
repo=$(cd "$(dirname "$0")/../.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

job() {  # job FRAMES: every stage kind but the report's scene pictures at their default size
  cat <<EOF
version: 1
output: out
cache: cache
stages:
  source: {kind: source, params: {format: synthetic, frames: $1, width: 64, height: 48}}
  calibrate: {kind: calibrate, needs: [source]}
  poses: {kind: poses, needs: [calibrate]}
  scene: {kind: reconstruct, needs: [poses], params: {every: 50}}
  annotations: {kind: annotations, needs: [source]}
  labels: {kind: propagate, needs: [poses, annotations]}
  dataset: {kind: export, needs: [labels]}
  report: {kind: report, needs: [labels, scene]}
EOF
}

seconds_of() { awk '{print $1}' "$1"; }
memory_of() { awk '{print $2}' "$1"; }
timed() {  # timed OUT COMMAND...: "seconds peak_kB" of the command into OUT
  local out=$1
  shift
  /usr/bin/time -f "%e %M" -o "$out" "$@" > /dev/null 2>&1
}

declare -A figure
for n in "$small" "$large"; do
  mkdir -p "$work/$n"
  job "$n" > "$work/$n/job.yaml"
  timed "$work/run" "$olt" run "$work/$n/job.yaml"
  figure[run_s_$n]=$(seconds_of "$work/run")
  figure[run_mb_$n]=$(( $(memory_of "$work/run") / 1024 ))
  timed "$work/plan" "$olt" plan "$work/$n/job.yaml"
  figure[plan_s_$n]=$(seconds_of "$work/plan")
  timed "$work/verify" "$olt" cache verify "$work/$n/job.yaml"
  figure[verify_s_$n]=$(seconds_of "$work/verify")
  timed "$work/gc" "$olt" cache gc "$work/$n/job.yaml"
  figure[gc_s_$n]=$(seconds_of "$work/gc")
  figure[files_$n]=$(find "$work/$n/out" -type f | wc -l)
done

printf '%-34s %12s %12s %8s\n' "" "$small obs." "$large obs." ratio
row() {  # row LABEL KEY
  local a=${figure[$2_$small]} b=${figure[$2_$large]}
  printf '%-34s %12s %12s %8s\n' "$1" "$a" "$b" "$(awk -v a="$a" -v b="$b" 'BEGIN { if (a > 0) printf "%.2f", b / a; else print "-" }')"
}
row "run, wall s" run_s
row "run, peak memory MB" run_mb
row "files published" files
row "olt plan, s" plan_s
row "olt cache verify, s" verify_s
row "olt cache gc, s" gc_s

# Start-up: a run with nothing to do (every stage cached), and `olt version` beside it.
mkdir -p "$work/quick"
cp -r "$repo/jobs" "$work/quick/jobs"
OLT_CACHE_DIR="$work/quick/cache" "$olt" run "$work/quick/jobs/quickstart.yaml" -q > /dev/null 2>&1
median_ms() {
  local times=()
  for _ in $(seq 21); do
    local start end
    start=$(date +%s%N)
    "$@" > /dev/null 2>&1
    end=$(date +%s%N)
    times+=($(( (end - start) / 1000000 )))
  done
  printf '%s\n' "${times[@]}" | sort -n | sed -n 11p
}
printf '%-34s %12s\n' "olt version, median ms" "$(median_ms "$olt" version)"
printf '%-34s %12s\n' "olt run, nothing to do, median ms" \
  "$(OLT_CACHE_DIR="$work/quick/cache" median_ms "$olt" run "$work/quick/jobs/quickstart.yaml" -q)"
