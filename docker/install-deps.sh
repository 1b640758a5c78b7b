#!/usr/bin/env bash
# Installs what OLT needs to build and test on Debian 12 (used by the README's quick start, by
# .ci/run and by container builds). Runs apt-get as root, or through sudo otherwise.
#   OLT_TEST_DEPS=0 bash docker/install-deps.sh     # build dependencies only
set -euo pipefail
packages=(
  cmake ninja-build g++ pkg-config
  libpcl-dev libeigen3-dev libyaml-cpp-dev nlohmann-json3-dev libspdlog-dev libopencv-dev
  catch2 libvalijson-dev libssl-dev libnanoflann-dev libpng-dev libjpeg-dev libcpp-httplib-dev libtbb-dev
  libmrpt-obs-dev
)
# For the test suite: a real Slurm cluster on localhost (tests/cluster/), MRPT's tools and data
# (rawlog-edit checks rawlog reading, icp-slam is the laser benchmark's peer, tests_rgbd.rawlog), and
# Chromium, which loads the report page headless (tests/stages/report_test.cpp); xfsprogs, for .ci/run's
# small XFS file system on which publishing's clones are tested.
# OLT_TEST_DEPS=0 leaves them out (the container image's build stage).
if [ "${OLT_TEST_DEPS:-1}" != 0 ]; then
  packages+=(slurmctld slurmd slurm-client mrpt-apps mrpt-common chromium xfsprogs)
fi
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
