#!/usr/bin/env bash
# The laser map's threads, in one process: ROUNDS builds of the real SENA loop's map with every
# thread and ROUNDS with one, in turn (the order swapped every round), idle and then with
# COMPETITORS CPU-bound processes (default 6) sharing the cores. threads_bench.sh times whole stages
# in separate processes, where a quarter-second stage moves by a fifth from run to run under load;
# taken in turn within one process, the two thread counts meet the same moments of the machine.
# Prints one row per load: the medians, their ratio (below 1: the threads help; the goal is never
# above 1), and the quartiles of the rounds' own ratios.
#   [ROUNDS=N] [COMPETITORS=N] bash tests/bench/laser_threads_bench.sh MAP_BENCH SHARED_DATA_DIR
set -euo pipefail
export LC_ALL=C
bench=$1
text="$2/mrpt_laser/text"
rounds=${ROUNDS:-21}
competitors=${COMPETITORS:-6}
if [ ! -f "$text/sena_scans.txt" ]; then
  echo "laser map threads: skipped, $text is absent"
  exit 0
fi
source "$(dirname "$0")/competitors.sh"
trap stop_load EXIT

printf '%-34s %-5s %9s %9s %7s %21s\n' "laser map, SENA loop, in turn" load "every s" "1 thr. s" ratio "rounds' ratios q1-q3"
for condition in idle busy; do
  if [ "$condition" = busy ]; then start_load "$competitors"; fi
  "$bench" "$text/sena_scans.txt" "$text/sena_odometry.txt" --threads "$rounds" |
    /usr/bin/python3 -c '
import json, sys
r = json.loads(sys.stdin.read())
print("%-34s %-5s %9.3f %9.3f %7.2f %16.2f-%.2f" % ("%d threads against 1, %d rounds" % (r["threads"], r["rounds"]),
      sys.argv[1], r["every_s"], r["one_s"], r["ratio"], r["round_ratio_q1"], r["round_ratio_q3"]))' "$condition"
done
