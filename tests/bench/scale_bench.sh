#!/usr/bin/env bash
# Scale and start-up: a synthetic hand-held recording of 1,000 and of 10,000 observations (64x48
# pixels, to keep it quick) labeled end to end; per size the run's wall time and peak memory, the
# same run again (nothing to do), then `olt plan`, `olt cache verify` and `olt cache gc` on its cache; and the time `olt run` takes when it
# has nothing to do (the median of 21, the quick start's job, cached). Ratios are 10,000 over 1,000,
# measured side by side in this one script. Then an edit, on a robot with 4 cameras of as many
# observations: every box moved, then the box the fewest observations see, each run's wall time.
# Box files of as many boxes read, and one of 100,000 refused.
#   bash tests/bench/scale_bench.sh build/olt [SMALL LARGE]
set -euo pipefail
olt=$(realpath "$1")
small=${2:-1000}
large=${3:-10000}
repo=$(cd "$(dirname "$0")/../.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# The scene fuses every 20th of the observations at either size (every: FRAMES / 20): the same 20
# observations' worth of points, for a scene's size is the job's choice (`every`, `voxel_size_m`),
# not the recording's length; what is measured is what the run holds per observation.
job() {  # job FRAMES: every stage kind but the report's scene pictures at their default size
  cat <<EOF
version: 1
output: out
cache: cache
stages:
  source: {kind: source, params: {format: synthetic, frames: $1, width: 64, height: 48}}
  calibrate: {kind: calibrate, needs: [source]}
  poses: {kind: poses, needs: [calibrate]}
  scene: {kind: reconstruct, needs: [poses], params: {every: $(($1 / 20))}}
  annotations: {kind: annotations, needs: [source]}
  labels: {kind: propagate, needs: [poses, annotations]}
  dataset: {kind: export, needs: [labels]}
  report: {kind: report, needs: [labels, scene]}
EOF
}

seconds_of() { awk 'END {print $1}' "$1"; }
memory_of() { awk 'END {print $2}' "$1"; }
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
  timed "$work/again" "$olt" run "$work/$n/job.yaml"
  figure[again_s_$n]=$(seconds_of "$work/again")
  timed "$work/plan" "$olt" plan "$work/$n/job.yaml"
  figure[plan_s_$n]=$(seconds_of "$work/plan")
  timed "$work/verify" "$olt" cache verify "$work/$n/job.yaml"
  figure[verify_s_$n]=$(seconds_of "$work/verify")
  timed "$work/gc" "$olt" cache gc "$work/$n/job.yaml"
  figure[gc_s_$n]=$(seconds_of "$work/gc")
  figure[files_$n]=$(find "$work/$n/out" -type f | wc -l)
done

# An edit at scale: a robot with 4 cameras (a quarter of the observations each), its boxes read
# from a file; every box moved, then the box the fewest observations see, each run timed.
robot_job() {  # robot_job OBSERVATIONS
  cat <<EOF
version: 1
output: out
cache: cache
stages:
  source: {kind: source, params: {format: synthetic, cameras: 4, frames: $(($1 / 4)), rate_hz: 2.5, width: 64, height: 48}}
  calibrate: {kind: calibrate, needs: [source]}
  poses: {kind: poses, needs: [calibrate], params: {method: trajectory}}
  scene: {kind: reconstruct, needs: [poses], params: {every: 50}}
  annotations: {kind: annotations, needs: [source, scene], params: {file: boxes.json, frame: world}}
  labels: {kind: propagate, needs: [poses, annotations]}
  dataset: {kind: export, needs: [labels]}
  report: {kind: report, needs: [labels, scene]}
EOF
}
move() {  # move BOXES_FILE all|ID: raises the boxes 1 cm
  /usr/bin/python3 -c 'import json, sys
boxes = json.load(open(sys.argv[1]))
for b in boxes["boxes"]:
    if sys.argv[2] in ("all", b["id"]):
        b["center"][2] += 0.01
json.dump(boxes, open(sys.argv[1], "w"))' "$1" "$2"
}
for n in "$small" "$large"; do
  dir="$work/robot$n"
  mkdir -p "$dir"
  robot_job "$n" | sed 's|, params: {file: boxes.json, frame: world}||' > "$dir/job.yaml"
  "$olt" run "$dir/job.yaml" > /dev/null 2>&1
  cp "$dir/out/annotations/boxes.json" "$dir/boxes.json"
  robot_job "$n" > "$dir/job.yaml"
  "$olt" run "$dir/job.yaml" > /dev/null 2>&1
  read -r fewest seeing < <(/usr/bin/python3 -c 'import json, sys
boxes = json.load(open(sys.argv[1]))["boxes"]
k = min(boxes, key=lambda k: (boxes[k]["frames_seeing"], k))
print(k, boxes[k]["frames_seeing"])' "$dir/out/labels.json")
  figure[edit_seen_$n]=$(awk -v a="$seeing" -v n="$n" 'BEGIN { printf "%.0f%%", 100 * a / n }')
  move "$dir/boxes.json" all
  timed "$work/edit" "$olt" run "$dir/job.yaml"
  figure[edit_all_s_$n]=$(seconds_of "$work/edit")
  move "$dir/boxes.json" "$fewest"
  timed "$work/edit" "$olt" run "$dir/job.yaml"
  figure[edit_one_s_$n]=$(seconds_of "$work/edit")
  figure[edit_share_$n]=$(awk -v a="${figure[edit_one_s_$n]}" -v b="${figure[edit_all_s_$n]}" 'BEGIN { printf "%.2f", a / b }')
done

# Box files: one of as many boxes as observations (up to 10,000, the most one file may hold) read, each
# box's corners printed; then one of 100,000 refused (exit 2, "at most": 10,000 is the limit).
boxes_file() {  # boxes_file COUNT: a native box file
  /usr/bin/python3 -c 'import sys
n = int(sys.argv[1])
box = "{\"id\": \"b%d\", \"label\": \"x\", \"center\": [0, 0, 1], \"size\": [0.1, 0.1, 0.1], \"rotation\": [0, 0, 0, 1]}"
print("{\"version\": 1, \"boxes\": [" + ",\n".join(box % i for i in range(n)) + "]}")' "$1"
}
for n in "$small" "$large"; do
  boxes_file $((n < 10000 ? n : 10000)) > "$work/boxes$n.json"
  timed "$work/boxes" "$olt" boxes corners "$work/boxes$n.json"
  figure[boxes_s_$n]=$(seconds_of "$work/boxes")
  figure[boxes_mb_$n]=$(( $(memory_of "$work/boxes") / 1024 ))
done
boxes_file 100000 > "$work/too_many.json"
timed "$work/refused" "$olt" boxes corners "$work/too_many.json" || true
refusal=$("$olt" boxes corners "$work/too_many.json" 2>&1 >/dev/null || true)
[[ $refusal == *"at most"* ]] || { echo "the box file of 100,000 was not refused: $refusal" >&2; exit 1; }

printf '%-34s %12s %12s %8s\n' "" "$small obs." "$large obs." ratio
row() {  # row LABEL KEY
  local a=${figure[$2_$small]} b=${figure[$2_$large]}
  printf '%-34s %12s %12s %8s\n' "$1" "$a" "$b" "$(awk -v a="$a" -v b="$b" 'BEGIN { if (a > 0) printf "%.2f", b / a; else print "-" }')"
}
row "run, wall s" run_s
row "run, peak memory MB" run_mb
row "files published" files
row "run again, nothing to do, s" again_s
row "olt plan, s" plan_s
row "olt cache verify, s" verify_s
row "olt cache gc, s" gc_s
row "robot: every box moved, wall s" edit_all_s
row "robot: one box moved, wall s" edit_one_s
row "  seen by (of the observations)" edit_seen
row "  share of every box moved" edit_share
row "box file of as many boxes, read, s" boxes_s
row "  peak memory MB" boxes_mb
printf '%-34s %12s\n' "box file of 100,000 refused, s" "$(seconds_of "$work/refused")"
printf '%-34s %12s\n' "  peak memory MB" "$(( $(memory_of "$work/refused") / 1024 ))"

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
