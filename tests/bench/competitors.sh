# CPU-bound competitors for the thread benchmarks (sourced): start_load N starts N busy loops, as
# other work on a shared workstation or an oversubscribed cluster node; stop_load ends them (the
# sourcing script calls it on exit too).
loads=()
start_load() {
  for _ in $(seq "$1"); do
    (while :; do :; done) &
    loads+=($!)
  done
}
stop_load() { for p in ${loads[@]+"${loads[@]}"}; do kill "$p" 2>/dev/null || true; done; loads=(); }
