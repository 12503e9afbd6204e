#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# CTest driver: installs the pinned npm test clients (package-lock.json) under the build tree and
# runs live_test.mjs against the real daemon. Exit 77 (reported as skipped) when node/npm are
# missing or the npm registry is unreachable.
set -euo pipefail
exe=$1
src=$2
source_dir=$3
work=$4
script=${5:-live_test.mjs}
if ! command -v node >/dev/null 2>&1 || ! command -v npm >/dev/null 2>&1; then
  echo "SKIP: node and npm are needed for the Foxglove client test (apt-get install nodejs npm)"
  exit 77
fi
mkdir -p "$work/node"
cp "$src/$script" "$src/harness.mjs" "$work/node/"
if ! cmp -s "$src/package-lock.json" "$work/node/package-lock.json" ||
   [ ! -d "$work/node/node_modules/@foxglove/ws-protocol" ]; then
  cp "$src/package.json" "$src/package-lock.json" "$work/node/"
  if ! (cd "$work/node" && npm ci --no-audit --no-fund --ignore-scripts >npm.log 2>&1); then
    cat "$work/node/npm.log" || true
    rm -f "$work/node/package-lock.json"  # retry the install next time
    echo "SKIP: npm ci failed (is the npm registry reachable?); cannot run the Foxglove client test"
    exit 77
  fi
fi
# The daemon's run directory holds its control socket, whose path must fit in 107 bytes; under a
# deep build tree it did not (a clone in /tmp/tmp.XXXXXXXXXX/c with build dir build-asan-g1).
run=$(mktemp -d "${TMPDIR:-/tmp}/coxswain-live.XXXXXX")
if [ "$script" = flood_test.mjs ]; then
  # 2,000 client connections and more: raise this shell's own descriptor limit.
  ulimit -n 8192 2>/dev/null || ulimit -n "$(ulimit -Hn)" 2>/dev/null || true
  if [ "$(ulimit -n)" != unlimited ] && [ "$(ulimit -n)" -lt 2300 ]; then
    echo "SKIP: the flood test needs 2,300 descriptors, the limit here is $(ulimit -n)"
    exit 77
  fi
fi
if node "$work/node/$script" "$exe" "$source_dir" "$run"; then
  rm -rf "$run"
else
  status=$?
  echo "run directory kept: $run"
  exit "$status"
fi
