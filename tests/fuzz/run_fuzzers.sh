#!/usr/bin/env bash
# Runs each libFuzzer target for SECONDS (default 60) on a copy of its committed seed corpus
# (tests/fuzz/corpus/<target>/), then replays every committed input (seeds and regressions). A
# crash's input is kept in FINDINGS_DIR (default: a temporary folder, printed) and fails the run.
#   bash tests/fuzz/run_fuzzers.sh BUILD_DIR [SECONDS]     (FUZZ_JOBS targets at once, default 2)
# The build: CC=clang-14 CXX=clang++-14 cmake -S . -B build-fuzz -G Ninja -DOLT_FUZZ=ON
#            -DOLT_BUILD_TESTS=OFF && cmake --build build-fuzz --target fuzz_targets
# (CI fuzzes from its sanitizer build, tests included: .ci/run.)
set -euo pipefail
build=$(realpath "$1")
seconds=${2:-60}
here=$(cd "$(dirname "$0")" && pwd)
findings=${FINDINGS_DIR:-$(mktemp -d /tmp/olt-fuzz-XXXXXX)}
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
jobs=${FUZZ_JOBS:-2}  # targets fuzzed at once (one core each)

# Fuzzes one target, then replays its committed inputs; returns non-zero on a crash.
fuzz_one() {
  local target=$1 work log runs
  work=$(mktemp -d)
  cp -r "$here/corpus/$target/." "$work/"
  log="$findings/$target.log"
  # Each target writes its crash inputs into FINDINGS_DIR/<target>-crash-*.
  if "$build/fuzz_$target" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="$findings/$target-" "$work" > "$log" 2>&1; then
    runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
    echo "fuzz_$target: ${seconds} s, $runs executions, corpus $(ls "$work" | wc -l) inputs, no crash"
  else
    echo "fuzz_$target: CRASH (see $log and $findings/$target-*)"
    tail -30 "$log"
    rm -rf "$work"
    return 1
  fi
  rm -rf "$work"
  # Regression inputs (earlier crashes) and seeds replayed once each.
  "$build/fuzz_$target" -runs=1 "$here/corpus/$target" > "$findings/$target-replay.log" 2>&1 \
    || { echo "fuzz_$target: a committed input fails again"; tail -30 "$findings/$target-replay.log"; return 1; }
}

status=0
running=()
for target in job annotations tum_list trajectory laser_text; do
  fuzz_one "$target" &
  running+=($!)
  if (( ${#running[@]} >= jobs )); then
    wait "${running[0]}" || status=1
    running=("${running[@]:1}")
  fi
done
for pid in "${running[@]}"; do wait "$pid" || status=1; done
echo "fuzz findings and logs: $findings"
exit $status
