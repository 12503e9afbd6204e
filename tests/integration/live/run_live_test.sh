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
# shellcheck source=../../support/npm_clients.sh
source "$src/../../support/npm_clients.sh"
install_npm_clients "$src" "$work/node" @foxglove/ws-protocol "the Foxglove client test"
cp "$src/$script" "$src/harness.mjs" "$work/node/"
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
