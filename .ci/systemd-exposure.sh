#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The systemd units' exposure by `systemd-analyze security --offline=true` must be at most 2.0
# (lower is better; 10 is a service with no sandboxing). Also checks the units' syntax.
# Usage: .ci/systemd-exposure.sh [MAX]   (run from the repository root)
set -euo pipefail
max=${1:-2.0}
if ! command -v systemd-analyze >/dev/null 2>&1; then
  echo "systemd-analyze is missing: apt-get install systemd" >&2
  exit 2
fi
status=0
for unit in systemd/coxswain.service systemd/coxswain@.service; do
  target=$unit
  tmp=""
  if [[ $unit == *@.service ]]; then
    # A template is analysed as one of its instances.
    tmp=$(mktemp -d)
    target="$tmp/coxswain@hopping.service"
    cp "$unit" "$target"
  fi
  out=$(systemd-analyze security --offline=true --no-pager "$target" 2>&1) || true
  [ -n "$tmp" ] && rm -rf "$tmp"
  level=$(printf '%s\n' "$out" | sed -n 's/.*Overall exposure level for [^:]*: \([0-9.]*\).*/\1/p')
  if [ -z "$level" ]; then
    printf '%s\n' "$out"
    echo "FAIL: no exposure level for $unit" >&2
    status=1
    continue
  fi
  if awk -v l="$level" -v m="$max" 'BEGIN { exit !(l <= m) }'; then
    echo "ok: $unit exposure $level (at most $max)"
  else
    printf '%s\n' "$out" | grep '✗' || true
    echo "FAIL: $unit exposure $level, more than $max" >&2
    status=1
  fi
done
exit $status
