#!/usr/bin/env bash
# Records what every shipped job publishes (path -> sha256 of each file but the manifest) into
# tests/golden/shipped_jobs.json, which tests/runtime/shipped_jobs_test.cpp compares every run with.
# Run it when an output is meant to change, and say why in the commit:
#   bash tests/golden/record.sh build/olt
# Each job runs from a copy of jobs/ (so outputs land outside the repository) on a fresh cache; a job
# whose data in ../shared/data is absent keeps its recorded digests.
set -euo pipefail
olt=$(realpath "$1")
repo=$(cd "$(dirname "$0")/../.." && pwd)
golden="$repo/tests/golden/shipped_jobs.json"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/repo"
cp -r "$repo/jobs" "$work/repo/jobs"
ln -s "$repo/../shared" "$work/shared"
[ -f "$golden" ] || echo '{}' > "$golden"
for job in "$repo"/jobs/*.yaml; do
  name=$(basename "$job" .yaml)
  data=$(grep -o '\.\./\.\./shared/data/[A-Za-z0-9_]*' "$job" | head -1 | sed 's#\.\./\.\./shared/data/##' || true)
  if [ -n "$data" ] && [ ! -d "$repo/../shared/data/$data" ]; then
    echo "$name: ../shared/data/$data is absent, digests kept"
    continue
  fi
  if ! OLT_CACHE_DIR="$work/cache-$name" "$olt" run "$work/repo/jobs/$name.yaml" > "$work/$name.log" 2>&1; then
    echo "$name: run failed, digests kept:"; tail -3 "$work/$name.log"; continue
  fi
  output=$(grep '^output:' "$job" | sed 's#^output: *##')
  manifest="$work/repo/jobs/$output/manifest.json"
  python3 - "$golden" "$name" "$data" "$work/repo/jobs/$output" <<'PY'
import hashlib, json, os, sys
golden_file, name, data, output = sys.argv[1:5]
golden = json.load(open(golden_file))
files = {}
for folder, _, names in os.walk(output):
    for n in names:
        path = os.path.relpath(os.path.join(folder, n), output)
        if path == "manifest.json":
            continue
        content = open(os.path.join(folder, n), "rb").read()
        files[path] = hashlib.sha256(content).hexdigest()
golden[name] = {"data": data, "files": dict(sorted(files.items()))}
json.dump(dict(sorted(golden.items())), open(golden_file, "w"), indent=1)
open(golden_file, "a").write("\n")
print("%s: %d files recorded" % (name, len(files)))
PY
done
