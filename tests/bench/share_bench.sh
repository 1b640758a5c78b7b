#!/usr/bin/env bash
# The robot's one-box share (issue 20, part 3: a one-box cycle over a full relabel) for one or
# more builds, each round running every build's `one` and `full` cycles (cycle_bench.py) back to
# back, so that a share's two figures meet the machine in the same minutes (taken minutes apart, the
# full relabel drifted by a fifth on this VM). Prints each round's cycles and share per build, then
# each build's median share.
#   TMPDIR=/dev/shm bash tests/bench/share_bench.sh ROUNDS OLT [OLT...]
set -euo pipefail
rounds=$1
shift
here=$(cd "$(dirname "$0")" && pwd)
declare -A shares
median_cycle() { sed -n 's/.*medians: cycle \([0-9.]*\) ms.*/\1/p'; }
for round in $(seq "$rounds"); do
  for olt in "$@"; do
    one=$(/usr/bin/python3 "$here/cycle_bench.py" "$olt" one --cycles 20 | median_cycle)
    full=$(/usr/bin/python3 "$here/cycle_bench.py" "$olt" full --cycles 15 | median_cycle)
    share=$(/usr/bin/python3 -c "print(f'{100 * $one / $full:.1f}')")
    echo "round $round, $olt: one box $one ms, full relabel $full ms, share $share %"
    shares[$olt]="${shares[$olt]:-} $share"
  done
done
for olt in "$@"; do
  echo "$olt: median share $(/usr/bin/python3 -c "import statistics, sys; print(statistics.median(float(s) for s in sys.argv[1:]))" ${shares[$olt]}) % (rounds:${shares[$olt]})"
done
