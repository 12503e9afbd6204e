#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Runs every libFuzzer target for a long bounded run (default 10^7 inputs each) and writes one
# summary line per target: inputs run, time, coverage, and whether it found anything (a crash
# file under OUT/<target>/). Builds the fuzz tree first (clang, -DCOXSWAIN_BUILD_FUZZ=ON).
# Usage: tools/fuzz/long.sh [RUNS] [BUILD_DIR] [OUT_DIR] [FILTER]   (from the repository root)
# FILTER, an extended regular expression, keeps the targets whose names match it (all by default),
# so the slow targets can run beside the fast ones.
# Each target runs single-process with a 4 KiB input limit and seed 1, as in CI; RUNS=10000000
# takes hours per target on one core.
set -euo pipefail
runs=${1:-10000000}
build=${2:-build-fuzz}
out=${3:-fuzz-long-$(date -u +%Y%m%d-%H%M%S)}
filter=${4:-.}
cmake -S . -B "$build" -G Ninja -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCOXSWAIN_BUILD_FUZZ=ON -DCOXSWAIN_BUILD_BENCH=OFF >/dev/null
cmake --build "$build" -j "$(nproc)" --target coxswain_fuzzers
mkdir -p "$out"
# Allocation stacks are not recorded (a third of an allocation-heavy target's time); a finding
# is re-run with the default options for its full report.
export ASAN_OPTIONS="${ASAN_OPTIONS:-malloc_context_size=0}"
summary="$out/summary.txt"
: >"$summary"
status=0
for exe in $(find "$build/tests/fuzz" -maxdepth 2 -type f -perm -u+x -name '*fuzz*' | sort); do
  name=$(basename "$exe")
  [[ "$name" =~ $filter ]] || continue
  mkdir -p "$out/$name/corpus"
  start=$(date +%s)
  if "$exe" -runs="$runs" -seed=1 -max_len=4096 -artifact_prefix="$out/$name/" \
      "$out/$name/corpus" >"$out/$name/log.txt" 2>&1; then
    result=clean
  else
    result="FOUND (see $out/$name/)"
    status=1
  fi
  secs=$(( $(date +%s) - start ))
  cov=$(grep -o 'cov: [0-9]*' "$out/$name/log.txt" | tail -1 || true)
  done_runs=$(grep -o 'Done [0-9]* runs' "$out/$name/log.txt" | tail -1 || true)
  echo "$name: ${done_runs:-stopped} in ${secs} s, ${cov:-cov: ?}, $result" | tee -a "$summary"
done
echo "summary: $summary"
exit $status
