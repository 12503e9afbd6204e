#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Sourced by the CTest drivers that run npm test clients.
# install_npm_clients SRC WORK MARKER WHAT: installs the clients pinned in SRC/package-lock.json
# into WORK (`npm ci`, no install scripts) unless WORK already holds that lock file and
# node_modules/MARKER. Exits 77 (reported as skipped) when node or npm is missing or the install
# fails (no registry); WHAT names the check in that message.
install_npm_clients() {
  local src=$1 work=$2 marker=$3 what=$4
  if ! command -v node >/dev/null 2>&1 || ! command -v npm >/dev/null 2>&1; then
    echo "SKIP: node and npm are needed for $what (apt-get install nodejs npm)"
    exit 77
  fi
  mkdir -p "$work"
  if ! cmp -s "$src/package-lock.json" "$work/package-lock.json" ||
     [ ! -d "$work/node_modules/$marker" ]; then
    cp "$src/package.json" "$src/package-lock.json" "$work/"
    if ! (cd "$work" && npm ci --no-audit --no-fund --ignore-scripts >npm.log 2>&1); then
      cat "$work/npm.log" || true
      rm -f "$work/package-lock.json"  # retry the install next time
      echo "SKIP: npm ci failed (is the npm registry reachable?); cannot run $what"
      exit 77
    fi
  fi
}
