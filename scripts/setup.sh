#!/usr/bin/env bash
# Installs vdtnav's build dependencies from Debian (idempotently: only what is missing; as root
# without sudo, with sudo otherwise), then configures and builds one configuration.
#
#   scripts/setup.sh [release|asan]        default: release
# Builds into build/<config>. Nothing is downloaded but Debian packages.
set -euo pipefail
cd "$(dirname "$0")/.."

config="${1:-release}"
packages=(build-essential cmake pkg-config git
          libeigen3-dev libyaml-cpp-dev libstb-dev zlib1g-dev
          libgtest-dev libgmock-dev libbenchmark-dev libopencv-dev libcli11-dev libceres-dev
          libpcl-dev liboctomap-dev)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "[setup] installing Debian packages: ${missing[*]}"
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

jobs="$(nproc)"
case "$config" in
  release)
    cmake -S . -B build/release -DCMAKE_BUILD_TYPE=Release -DVDTNAV_WERROR=ON >/dev/null
    ;;
  asan)
    # Sanitized tests only: examples and benchmarks are exercised by the release build.
    # -O1 with line tables only: fast to compile, enough for sanitizer stack traces.
    cmake -S . -B build/asan -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g1" \
      -DVDTNAV_WERROR=ON -DVDTNAV_SANITIZE=ON -DVDTNAV_BUILD_EXAMPLES=OFF \
      -DVDTNAV_BUILD_BENCHMARKS=OFF -DVDTNAV_BUILD_FRONTENDS=OFF >/dev/null
    ;;
  *) echo "usage: scripts/setup.sh [release|asan]" >&2; exit 2 ;;
esac
echo "[setup] building build/$config with $jobs jobs"
cmake --build "build/$config" -j "$jobs"
