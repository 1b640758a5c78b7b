#!/usr/bin/env bash
# Builds the OLT container images with podman, fully offline (no container registry): olt:latest
# (the default target) and olt:full (MRPT rawlogs and OpenCV's other image formats), then runs every
# shipped job in them and compares the bytes with the recorded ones (docker/check-image.sh).
#
#   bash docker/build-image.sh            # from the repository root
#
# Steps: install podman/runc/debootstrap if missing (apt-get, as root or through sudo); write a
# containers.conf (runtime runc: crun refuses this machine's hybrid cgroups; ulimits within the
# machine's hard limits); make docker.io/library/debian:bookworm with debootstrap if it is not in
# local storage, and debian:bookworm-slim from it (its documentation, manual pages and translations
# left out, as Debian's own slim image does); podman build of both targets; check-image.sh on each.
#
# Environment: IMAGE (default olt:latest; the full image is its name with the tag "full"),
# DEBIAN_MIRROR (default http://deb.debian.org/debian).
set -euo pipefail

IMAGE="${IMAGE:-olt:latest}"
# The same name with the tag "full" (a reference without a tag, host:port/name included, gets one).
name="$IMAGE"
[[ "${IMAGE##*/}" == *:* ]] && name="${IMAGE%:*}"
FULL_IMAGE="$name:full"
BASE_IMAGE="docker.io/library/debian:bookworm"
SLIM_IMAGE="docker.io/library/debian:bookworm-slim"
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
if podman image exists "$SLIM_IMAGE"; then
  log "base image $SLIM_IMAGE present"
else
  # Debian's slim image: the same packages, without /usr/share/{doc,man,info,locale} (the copyright
  # files kept), ~50 MB less.
  log "making $SLIM_IMAGE from $BASE_IMAGE"
  container=$(podman create "$BASE_IMAGE" true)
  podman export "$container" | /usr/bin/python3 -c '
import re, sys, tarfile
drop = re.compile(r"^(\./)?usr/share/(man|info|locale|doc)/")
keep = re.compile(r"^(\./)?usr/share/doc/[^/]+/copyright$")
source = tarfile.open(fileobj=sys.stdin.buffer, mode="r|")
target = tarfile.open(fileobj=sys.stdout.buffer, mode="w|")
for member in source:
    if drop.match(member.name) and not keep.match(member.name) and not member.isdir():
        continue
    target.addfile(member, source.extractfile(member) if member.isfile() else None)
target.close()' | podman import --change 'CMD ["bash"]' - "$SLIM_IMAGE" >/dev/null
  podman rm "$container" >/dev/null
fi
t_base=$((SECONDS - t0))

# --- 4. image build ---------------------------------------------------------------------------
t0=$SECONDS
log "podman build -f docker/Dockerfile -t $IMAGE ."
podman build -f docker/Dockerfile -t "$IMAGE" . || die "podman build failed"
log "podman build -f docker/Dockerfile --target full -t $FULL_IMAGE ."
podman build -f docker/Dockerfile --target full -t "$FULL_IMAGE" . || die "podman build --target full failed"
t_build=$((SECONDS - t0))
log "images built in $(elapsed $t_build)"

# --- 5. every shipped job in each image, its bytes compared with the recorded ones --------------
t0=$SECONDS
for image in "$IMAGE" "$FULL_IMAGE"; do
  log "docker/check-image.sh $image"
  bash docker/check-image.sh "$image" || die "a shipped job failed or gave other bytes in $image"
done
t_run=$((SECONDS - t0))

# --- 6. summary -------------------------------------------------------------------------------
for image in "$IMAGE" "$FULL_IMAGE"; do
  size=$(podman image inspect --format '{{.Size}}' "$image")
  log "image $image: $((size / 1000000)) MB ($size bytes)"
done
log "timings: base image $(elapsed $t_base), build $(elapsed $t_build), jobs $(elapsed $t_run), total $(elapsed $((SECONDS - t_start)))"
log "OK"
