#!/usr/bin/env bash
# A/B on a noisy machine: a benchmark command run with a baseline `olt` and a new one in turn, ROUNDS
# times, so both meet the machine in the same states; every run's table is printed, labeled.
#   bash tests/bench/ab.sh BASE_OLT NEW_OLT ROUNDS COMMAND...   ({} in COMMAND is the binary)
# e.g. bash tests/bench/ab.sh /tmp/base/build/olt build/olt 3 /usr/bin/python3 tests/bench/edit_bench.py {} --repeats 3
set -euo pipefail
base=$(realpath "$1") new=$(realpath "$2") rounds=$3
shift 3
for round in $(seq "$rounds"); do
  for label in base new; do
    binary=$base
    [ "$label" = new ] && binary=$new
    echo "== round $round, $label ($binary)"
    "${@//\{\}/$binary}"
  done
done
