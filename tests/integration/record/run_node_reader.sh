#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# CTest driver: installs the pinned npm test clients (package-lock.json) under the build tree,
# writes a recording with every channel and opens it with @mcap/core (read_mcap.mjs).
# Exit 77 (reported as skipped) when node/npm are missing or the npm registry is unreachable.
set -euo pipefail
writer=$1
src=$2
work=$3
if ! command -v node >/dev/null 2>&1 || ! command -v npm >/dev/null 2>&1; then
  echo "SKIP: node and npm are needed to open the recording with @mcap/core (apt-get install nodejs npm)"
  exit 77
fi
mkdir -p "$work/node"
cp "$src/read_mcap.mjs" "$work/node/"
if ! cmp -s "$src/package-lock.json" "$work/node/package-lock.json" ||
   [ ! -d "$work/node/node_modules/@mcap/core" ]; then
  cp "$src/package.json" "$src/package-lock.json" "$work/node/"
  if ! (cd "$work/node" && npm ci --no-audit --no-fund --ignore-scripts >npm.log 2>&1); then
    cat "$work/node/npm.log" || true
    rm -f "$work/node/package-lock.json"  # retry the install next time
    echo "SKIP: npm ci failed (is the npm registry reachable?); cannot run the @mcap/core check"
    exit 77
  fi
fi
"$writer" "$work/sample.mcap" "$work/expected.json"
node "$work/node/read_mcap.mjs" "$work/sample.mcap" "$work/expected.json"
