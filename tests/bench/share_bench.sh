#!/usr/bin/env bash
# The robot's one-box share (issue 20, part 3: a one-box cycle over a full relabel) for one or
# more builds: each round runs every build's `share` case of cycle_bench.py in turn, one-box cycles
# and full relabels taken in pairs in one daemon, so that a share's two figures meet the machine in
# the same seconds (taken as separate runs minutes apart, the full relabel drifted by a fifth to a
# quarter on this VM). Prints each round's figures per build, then each build's median share.
#   TMPDIR=/dev/shm bash tests/bench/share_bench.sh ROUNDS OLT [OLT...]
set -euo pipefail
rounds=$1
shift
here=$(cd "$(dirname "$0")" && pwd)
declare -A shares
for round in $(seq "$rounds"); do
  for olt in "$@"; do
    line=$(/usr/bin/python3 "$here/cycle_bench.py" "$olt" share --cycles 8 | grep "pairs of one-box")
    share=$(sed -n 's/.*; share \([0-9.]*\) %.*/\1/p' <<< "$line")
    echo "round $round, $olt: ${line#*in turn }"
    shares[$olt]="${shares[$olt]:-} $share"
  done
done
for olt in "$@"; do
  echo "$olt: median share $(/usr/bin/python3 -c "import statistics, sys; print(statistics.median(float(s) for s in sys.argv[1:]))" ${shares[$olt]}) % (rounds:${shares[$olt]})"
done
