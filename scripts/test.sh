#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Set up, build (warnings are errors) and run the whole test suite.
#   scripts/test.sh                                   release build in ./build, every test
#   COXSWAIN_SANITIZE="address;undefined" scripts/test.sh
#                                                     the same suite under AddressSanitizer and
#                                                     UndefinedBehaviorSanitizer in ./build-asan
#                                                     (what CI runs)
# COXSWAIN_JOBS sets the parallelism (default 2); COXSWAIN_UNITY=ON builds in unity batches
# (fewer, larger compiler runs: faster on a fresh machine, no incremental benefit);
# COXSWAIN_BENCH=OFF leaves the benchmarks out of the sanitizer build (they are never run there).
set -euo pipefail
cd "$(dirname "$0")/.."
jobs="${COXSWAIN_JOBS:-2}"
if [ -z "${COXSWAIN_SANITIZE:-}" ]; then
  scripts/setup.sh
  ctest --test-dir build --output-on-failure -j "$jobs"
  exit 0
fi

scripts/setup.sh --deps
unity=()
if [ "${COXSWAIN_UNITY:-OFF}" = "ON" ]; then
  unity=(-DCMAKE_UNITY_BUILD=ON -DCMAKE_UNITY_BUILD_BATCH_SIZE=16)
fi
# Line tables only (-g1): reports keep file:line and the tree stays small; -O1 keeps it quick.
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=Debug -DCOXSWAIN_WERROR=ON \
  -DCOXSWAIN_SANITIZE="$COXSWAIN_SANITIZE" -DCMAKE_CXX_FLAGS="-O1" -DCMAKE_CXX_FLAGS_DEBUG="-g1" \
  -DCOXSWAIN_BUILD_BENCH="${COXSWAIN_BENCH:-ON}" \
  "${unity[@]}"
cmake --build build-asan -j "$jobs"
ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}" \
UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}" \
  ctest --test-dir build-asan --output-on-failure -j "$jobs"
