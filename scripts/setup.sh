#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Installs every Debian 12 package coxswain needs (idempotent, non-interactive; run as root or
# with sudo available) and builds the project into ./build.
#   scripts/setup.sh            packages + build
#   scripts/setup.sh --deps     packages only
#   COXSWAIN_EXTRA_PACKAGES="clang ..." adds packages (CI uses it for the sanitizer/fuzz tools).
set -euo pipefail
cd "$(dirname "$0")/.."

PACKAGES=(
  build-essential cmake ninja-build pkg-config git
  libeigen3-dev libopencv-core-dev libopencv-imgproc-dev libopencv-imgcodecs-dev
  libopencv-videoio-dev libboost-dev libspdlog-dev libyaml-cpp-dev libcli11-dev libsystemd-dev
  libgeographiclib-dev nlohmann-json3-dev libzstd-dev libgtest-dev libgmock-dev libbenchmark-dev
)
# shellcheck disable=SC2206
PACKAGES+=(${COXSWAIN_EXTRA_PACKAGES:-})

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ "${#missing[@]}" -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  $SUDO env DEBIAN_FRONTEND=noninteractive apt-get update -qq
  $SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
    "${missing[@]}"
else
  echo "setup: all packages present"
fi

if [ "${1:-}" = "--deps" ]; then exit 0; fi

cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCOXSWAIN_WERROR=ON
cmake --build build -j "${COXSWAIN_JOBS:-2}"
