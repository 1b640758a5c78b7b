#!/usr/bin/env bash
# Builds the OLT container image with podman, fully offline (no container registry), then runs the
# quick-start job inside it as a smoke test.
#
#   bash docker/build-image.sh            # from the repository root
#
# Steps: install podman/runc/debootstrap if missing (apt-get, as root or through sudo); write a
# containers.conf (runtime runc: crun refuses this machine's hybrid cgroups; ulimits within the
# machine's hard limits); make docker.io/library/debian:bookworm with debootstrap if it is not in
# local storage; podman build; podman run of jobs/quickstart.yaml; check manifest.json.
#
# Environment: IMAGE (default olt:latest), DEBIAN_MIRROR (default http://deb.debian.org/debian).
set -euo pipefail

IMAGE="${IMAGE:-olt:latest}"
BASE_IMAGE="docker.io/library/debian:bookworm"
DEBIAN_MIRROR="${DEBIAN_MIRROR:-http://deb.debian.org/debian}"

log() { printf '[build-image %s] %s\n' "$(date +%H:%M:%S)" "$*"; }
die() { printf '[build-image] ERROR: %s\n' "$*" >&2; exit 1; }

[ -f docker/Dockerfile ] && [ -f CMakeLists.txt ] \
  || die "run from the repository root: bash docker/build-image.sh"
REPO_ROOT="$(pwd)"

sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"

tmp="$(mktemp -d "${TMPDIR:-/tmp}/olt-image.XXXXXX")"
rootfs=""
cleanup() {
  # The debootstrap tree has root-owned device nodes: remove it as root.
  [ -n "$rootfs" ] && [ -d "$rootfs" ] && $sudo rm -rf "$rootfs"
  rm -rf "$tmp" 2>/dev/null || $sudo rm -rf "$tmp"
}
trap cleanup EXIT

t_start=$SECONDS
elapsed() { echo "$(( $1 / 60 ))m$(( $1 % 60 ))s"; }

# --- 1. tools ---------------------------------------------------------------------------------
missing=()
for p in podman runc debootstrap; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  log "installing ${missing[*]}"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
log "$(podman --version)"

# --- 2. containers.conf -----------------------------------------------------------------------
cat >"$tmp/containers.conf" <<'EOF'
[containers]
default_ulimits = ["nofile=16384:16384", "nproc=16384:16384"]

[engine]
runtime = "runc"
EOF
export CONTAINERS_CONF="$tmp/containers.conf"
log "CONTAINERS_CONF=$CONTAINERS_CONF (runtime runc, ulimits nofile/nproc 16384)"

# --- 3. base image ----------------------------------------------------------------------------
t0=$SECONDS
if podman image exists "$BASE_IMAGE"; then
  log "base image $BASE_IMAGE present"
else
  log "base image $BASE_IMAGE missing: debootstrap --variant=minbase bookworm ($DEBIAN_MIRROR)"
  rootfs="$tmp/rootfs"
  $sudo debootstrap --variant=minbase bookworm "$rootfs" "$DEBIAN_MIRROR" >"$tmp/debootstrap.log" 2>&1 \
    || { tail -n 30 "$tmp/debootstrap.log" >&2; die "debootstrap failed"; }
  # Drop the downloaded .debs and package lists (~85 MB): every Dockerfile stage runs apt-get update.
  $sudo find "$rootfs/var/cache/apt/archives" "$rootfs/var/lib/apt/lists" -type f -delete
  $sudo tar -C "$rootfs" -c . | podman import - "$BASE_IMAGE" >/dev/null
  $sudo rm -rf "$rootfs"
  rootfs=""
  log "imported $BASE_IMAGE in $(elapsed $((SECONDS - t0)))"
fi
t_base=$((SECONDS - t0))

# --- 4. image build ---------------------------------------------------------------------------
t0=$SECONDS
log "podman build -f docker/Dockerfile -t $IMAGE ."
podman build -f docker/Dockerfile -t "$IMAGE" . || die "podman build failed"
t_build=$((SECONDS - t0))
log "image built in $(elapsed $t_build)"

# --- 5. smoke test: the quick-start job in the container ---------------------------------------
# Output and cache paths are relative to the job file, so the job is copied into a writable
# folder mounted at /work (the image's /opt/olt copy stays untouched).
t0=$SECONDS
work="$tmp/work"
mkdir -p "$work"
cp -r "$REPO_ROOT/jobs" "$work/jobs"
log "podman run --rm -v $work:/work $IMAGE run /work/jobs/quickstart.yaml"
set +e
podman run --rm -v "$work:/work" "$IMAGE" run /work/jobs/quickstart.yaml
rc=$?
set -e
[ "$rc" -eq 0 ] || die "olt run in the container exited $rc"
manifest="$work/out/quickstart/manifest.json"
[ -s "$manifest" ] || die "no $manifest after the run"
t_run=$((SECONDS - t0))
log "quick-start job ok in $(elapsed $t_run): out/quickstart/manifest.json ($(stat -c %s "$manifest") bytes)"

# --- 6. summary -------------------------------------------------------------------------------
size=$(podman image inspect --format '{{.Size}}' "$IMAGE")
log "image $IMAGE: $((size / 1000000)) MB ($size bytes)"
log "timings: base image $(elapsed $t_base), build $(elapsed $t_build), smoke run $(elapsed $t_run), total $(elapsed $((SECONDS - t_start)))"
log "OK"
