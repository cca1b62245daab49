#!/usr/bin/env bash
# Installs vdtnav's build dependencies from Debian (idempotently: only what is missing; as root
# without sudo, with sudo otherwise), then configures and builds one configuration.
#
#   scripts/setup.sh [release|asan|fuzz] [TARGET...]   default: release
#   (the targets given, default all of them; fuzz: default all the libFuzzer targets;
#   scripts/main.sh builds release's vdtnav_main_job: the studies, the CLI and Python only)
# Builds into build/<config>. Nothing is downloaded but Debian packages.
set -euo pipefail
cd "$(dirname "$0")/.."

config="${1:-release}"
packages=(build-essential cmake pkg-config git
          libeigen3-dev libyaml-cpp-dev libstb-dev zlib1g-dev
          libgtest-dev libgmock-dev libbenchmark-dev libopencv-dev libcli11-dev libceres-dev
          libpcl-dev liboctomap-dev
          librosbag-storage-dev libtf2-dev libsensor-msgs-dev libnav-msgs-dev libgeometry-msgs-dev
          libtf2-msgs-dev libfastcdr-dev libsqlite3-dev libfastrtps-dev cyclonedds-dev cyclonedds-tools
          libroscpp-dev libtf2-ros-dev libstd-srvs-dev libdiagnostic-msgs-dev ros-core
          pybind11-dev python3-dev python3-numpy python3-pytest python3-matplotlib)
if [ "$config" = fuzz ]; then packages+=(clang-14 libclang-rt-14-dev); fi

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
    cmake -S . -B build/release -DCMAKE_BUILD_TYPE=Release -DVDTNAV_WERROR=ON -DVDTNAV_PYTHON=ON \
      >/dev/null
    ;;
  asan)
    # Sanitized tests only: examples and benchmarks are exercised by the release build.
    # -O1 with line tables only: fast to compile, enough for sanitizer stack traces.
    # VDTNAV_TEST_ONLY (environment): the tests of these folders of tests/ only, e.g.
    # "core;map;sensor;io;sim" (scripts/test.sh); unset: every test.
    cmake -S . -B build/asan -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g1" \
      -DVDTNAV_WERROR=ON -DVDTNAV_SANITIZE=ON -DVDTNAV_BUILD_EXAMPLES=OFF \
      -DVDTNAV_BUILD_BENCHMARKS=OFF -DVDTNAV_BUILD_FRONTENDS=OFF -DVDTNAV_PYTHON=OFF \
      -DVDTNAV_TEST_ONLY="${VDTNAV_TEST_ONLY:-}" >/dev/null
    ;;
  fuzz)
    # The parsers' libFuzzer targets only: clang, the library with fuzzer coverage and sanitizers.
    cmake -S . -B build/fuzz -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_COMPILER=clang++-14 \
      -DCMAKE_C_COMPILER=clang-14 -DCMAKE_CXX_FLAGS="-fsanitize=fuzzer-no-link" \
      -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g1" -DVDTNAV_SANITIZE=ON -DVDTNAV_BUILD_FUZZERS=ON \
      -DVDTNAV_BUILD_TESTS=OFF -DVDTNAV_BUILD_EXAMPLES=OFF -DVDTNAV_BUILD_BENCHMARKS=OFF \
      -DVDTNAV_BUILD_TOOLS=OFF -DVDTNAV_BUILD_FRONTENDS=OFF -DVDTNAV_PYTHON=OFF >/dev/null
    shift || true
    targets=("${@:-vdtnav_fuzzers}")
    echo "[setup] building ${targets[*]} in build/fuzz with $jobs jobs"
    cmake --build build/fuzz -j "$jobs" --target "${targets[@]}"
    exit 0
    ;;
  *) echo "usage: scripts/setup.sh [release|asan|fuzz]" >&2; exit 2 ;;
esac
shift || true
if (($#)); then
  echo "[setup] building $* in build/$config with $jobs jobs"
  cmake --build "build/$config" -j "$jobs" --target "$@"
else
  echo "[setup] building build/$config with $jobs jobs"
  cmake --build "build/$config" -j "$jobs"
fi
