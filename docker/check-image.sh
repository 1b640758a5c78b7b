#!/usr/bin/env bash
# Runs every shipped job inside a container image and compares what it publishes with the digests
# the test suite holds (tests/golden/shipped_jobs.json): the image gives the bytes the build tree
# gives. Jobs whose recording in ../shared/data is absent are skipped, saying so; a job that reads
# an MRPT rawlog needs olt:full and is skipped in an image without MRPT, saying so.
#
#   bash docker/check-image.sh olt:latest      # from the repository root, after build-image.sh
set -euo pipefail
image=${1:?usage: check-image.sh IMAGE}
repo=$(pwd)
[ -f "$repo/tests/golden/shipped_jobs.json" ] || { echo "run from the repository root" >&2; exit 2; }
work=$(mktemp -d "${TMPDIR:-/tmp}/olt-check.XXXXXX")
trap 'rm -rf "$work" 2>/dev/null || true' EXIT
mkdir -p "$work/repo"
cp -r "$repo/jobs" "$work/repo/jobs"
shared=$(realpath "$repo/../shared" 2>/dev/null || true)
mounts=(-v "$work:/w")
[ -n "$shared" ] && [ -d "$shared" ] && mounts+=(-v "$shared:/w/shared:ro")
has_rawlog=$(podman run --rm --entrypoint sh "$image" -c 'test -f /usr/local/lib/olt/libolt_rawlog.so && echo yes || echo no')

failed=0
for job in "$repo"/jobs/*.yaml; do
  name=$(basename "$job" .yaml)
  data=$(grep -o '\.\./\.\./shared/data/[A-Za-z0-9_]*' "$job" | head -1 | sed 's#\.\./\.\./shared/data/##' || true)
  if [ -n "$data" ] && [ ! -d "$repo/../shared/data/$data" ]; then
    echo "$name: skipped, ../shared/data/$data is absent"
    continue
  fi
  if grep -q 'format: *rawlog' "$job" && [ "$has_rawlog" != yes ]; then
    echo "$name: skipped, reads an MRPT rawlog (olt:full has MRPT; this image does not)"
    continue
  fi
  if ! podman run --rm "${mounts[@]}" -e OLT_CACHE_DIR="/w/cache-$name" "$image" run -q "/w/repo/jobs/$name.yaml" \
    > "$work/$name.log" 2>&1; then
    echo "$name: FAILED in the image:"; tail -5 "$work/$name.log"; failed=1; continue
  fi
  output=$(grep '^output:' "$job" | sed 's#^output: *##')
  /usr/bin/python3 - "$repo/tests/golden/shipped_jobs.json" "$name" "$work/repo/jobs/$output" <<'PY' || failed=1
import hashlib, json, os, sys
golden_file, name, output = sys.argv[1:4]
want = json.load(open(golden_file))[name]["files"]
got = {}
for folder, _, names in os.walk(output):
    for n in names:
        path = os.path.relpath(os.path.join(folder, n), output)
        if path != "manifest.json":
            got[path] = hashlib.sha256(open(os.path.join(folder, n), "rb").read()).hexdigest()
differ = sorted(p for p in set(want) | set(got) if want.get(p) != got.get(p))
if differ:
    print("%s: FAILED, %d of %d files differ from the recorded bytes, e.g. %s" % (name, len(differ), len(want), differ[:3]))
    sys.exit(1)
print("%s: %d files, the recorded bytes" % (name, len(got)))
PY
done
exit $failed
