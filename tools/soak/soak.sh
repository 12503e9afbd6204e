#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Soak: the unmodified daemon in devices mode (coxswain-sim devices) for a long run with random
# faults on every serial device (unplug, USB reset, garbage, silence, baud change; drawn from a
# seed) and, every 30 s, the live-server flood of the flood test (2,000 idle connections, 50 idle
# control-socket connections, unauthenticated requests, a WebSocket client that never reads).
# The course (about 2 minutes) is sailed once; the daemon then stays up in its finished state
# while the faults and the floods go on (--run-past-finish), so one daemon process is measured
# for the whole duration.
# Checks: no crash (the daemon ran to the end and exited 0 on SIGTERM), every fault held (when
# the mission was sailing) and recovered (the device running again, the mission resumed), the
# course completed, and the daemon's resident memory grew by at most 5 MB from the baseline
# (taken once the devices run, the course is under way and the first flood is over) to the end.
# Usage: tools/soak/soak.sh [--duration-s S] [--seed N] [--build DIR] [--work DIR] [--no-flood]
#   defaults: 1800 s, seed 1, build/, a temporary directory (removed when the soak passes).
# Exit 0 passed, 1 failed, 77 skipped (no node/npm for the flood: use --no-flood).
set -euo pipefail
duration_s=1800
seed=1
build=build
work=""
flood=1
max_growth_kb=5120
while [ $# -gt 0 ]; do
  case $1 in
    --duration-s) duration_s=$2; shift 2 ;;
    --seed) seed=$2; shift 2 ;;
    --build) build=$2; shift 2 ;;
    --work) work=$2; shift 2 ;;
    --no-flood) flood=0; shift ;;
    *) echo "usage: $0 [--duration-s S] [--seed N] [--build DIR] [--work DIR] [--no-flood]" >&2
       exit 2 ;;
  esac
done
src=$(cd "$(dirname "$0")/../.." && pwd)
sim=$build/tools/sim/app/coxswain-sim
[ -x "$sim" ] || { echo "soak: $sim not built" >&2; exit 2; }
if [ "$duration_s" -lt 150 ]; then
  echo "soak: --duration-s must be at least 150 (the course takes about 2 minutes)" >&2
  exit 2
fi
keep_work=1
if [ -z "$work" ]; then
  work=$(mktemp -d "${TMPDIR:-/tmp}/coxswain-soak.XXXXXX")
  keep_work=0
fi
mkdir -p "$work"
run=$work/run
rm -rf "$run"

# The flood client: the flood test's own (tests/integration/live), with its pinned npm packages.
if [ "$flood" = 1 ]; then
  if ! command -v node >/dev/null 2>&1 || ! command -v npm >/dev/null 2>&1; then
    echo "SKIP: node and npm are needed for the flood (or pass --no-flood)"
    exit 77
  fi
  live=$src/tests/integration/live
  mkdir -p "$work/node"
  cp "$live/flood_test.mjs" "$live/harness.mjs" "$work/node/"
  if [ ! -d "$work/node/node_modules/ws" ]; then
    cp "$live/package.json" "$live/package-lock.json" "$work/node/"
    if ! (cd "$work/node" && npm ci --no-audit --no-fund --ignore-scripts >npm.log 2>&1); then
      cat "$work/node/npm.log" || true
      echo "SKIP: npm ci failed (is the npm registry reachable?); or pass --no-flood"
      exit 77
    fi
  fi
  # 2,000 client connections per flood: raise the descriptor limit (inherited by everything).
  ulimit -n 8192 2>/dev/null || ulimit -n "$(ulimit -Hn)" 2>/dev/null || true
  if [ "$(ulimit -n)" != unlimited ] && [ "$(ulimit -n)" -lt 2300 ]; then
    echo "SKIP: the flood needs 2,300 descriptors, the limit here is $(ulimit -n)"
    exit 77
  fi
fi

# Random faults from the seed: one at a time, every device, every kind, from 25 s (the mission
# is under way) to 15 s before the end, each followed by 8-16 s for the daemon to recover.
RANDOM=$seed
devices=(lidar imu gnss arduino)
kinds=(unplug reset garbage silence baud)
faults=()
t=25
while :; do
  device=${devices[RANDOM % 4]}
  kind=${kinds[RANDOM % 5]}
  if [ "$kind" = reset ]; then
    dur=0.$((3 + RANDOM % 7))
  else
    dur=$((1 + RANDOM % 4))
  fi
  [ $((t + 5)) -lt $((duration_s - 15)) ] || break
  faults+=(--fault "$device:$kind@$t+$dur")
  t=$((t + ${dur%.*} + 8 + RANDOM % 9))
done

rss_kb() { awk '/^VmRSS:/ {print $2}' "/proc/$1/status" 2>/dev/null || echo 0; }
fd_count() { ls "/proc/$1/fd" 2>/dev/null | wc -l; }

echo "soak: seed $seed, ${duration_s} s, $(( ${#faults[@]} / 2 )) faults, flood $([ $flood = 1 ] && echo on || echo off), work $work"
start_s=$(date +%s)
"$sim" devices --course "$src/config/courses/kaboat2026.yaml" --seed "$seed" --run-dir "$run" \
  --time-limit "$duration_s" --run-past-finish --live-port 0 --quiet --no-progress \
  "${faults[@]}" >"$work/sim.out" 2>"$work/sim.err" &
sim_pid=$!
cleanup() { kill "$sim_pid" 2>/dev/null || true; }
trap cleanup EXIT

daemon_pid=""
for _ in $(seq 1 300); do
  daemon_pid=$(pgrep -P "$sim_pid" -x coxswain || true)
  [ -n "$daemon_pid" ] && break
  sleep 0.1
done
[ -n "$daemon_pid" ] || { echo "FAIL: the daemon never started"; cat "$work/sim.err"; exit 1; }
port_file=""
for _ in $(seq 1 300); do
  port_file=$(ls "$run"/daemon/*/live.port 2>/dev/null | head -1 || true)
  [ -n "$port_file" ] && [ -s "$port_file" ] && break
  sleep 0.1
done
port=$(cat "$port_file")
sock=$run/control.sock
sleep 5
rss_boot=$(rss_kb "$daemon_pid")
fds_boot=$(fd_count "$daemon_pid")

# The floods: 8 s each, every 30 s, until 20 s before the end.
floods=0
flood_failures=0
rss_base=""
rss_peak=$rss_boot
next_flood=$((start_s + 30))
baseline_at=$((start_s + 70))
end_at=$((start_s + duration_s - 10))
rss_end=""
while kill -0 "$sim_pid" 2>/dev/null; do
  now=$(date +%s)
  r=$(rss_kb "$daemon_pid")
  [ "$r" -gt "$rss_peak" ] && rss_peak=$r
  if [ -z "$rss_base" ] && [ "$now" -ge "$baseline_at" ]; then
    rss_base=$r
    fds_base=$(fd_count "$daemon_pid")
  fi
  if [ "$now" -ge "$end_at" ]; then
    rss_end=$r
    fds_end=$(fd_count "$daemon_pid")
    break
  fi
  if [ "$flood" = 1 ] && [ "$now" -ge "$next_flood" ] && [ "$now" -lt $((end_at - 20)) ]; then
    if node "$work/node/flood_test.mjs" --flood "$port" "$sock" 8 >>"$work/flood.out" \
        2>>"$work/flood.err"; then
      floods=$((floods + 1))
    else
      flood_failures=$((flood_failures + 1))
    fi
    next_flood=$((next_flood + 30))
    continue
  fi
  sleep 1
done
wait "$sim_pid" && sim_status=0 || sim_status=$?
trap - EXIT
elapsed=$(( $(date +%s) - start_s ))

# ---- the figures ----
out=$work/sim.out
faults_line=$(grep -m1 '^faults: ' "$out" || echo "faults: none")
run_line=$(grep -m1 '^run ended: ' "$out" || echo "run ended: ?")
score_line=$(grep -m1 '^score: ' "$out" || echo "score: ?")
daemon_line=$(grep -m1 '^daemon: ' "$out" || echo "daemon: ?")
requests=$(grep -o '"requests":[0-9]*' "$work/flood.out" 2>/dev/null | cut -d: -f2 |
  awk '{s += $1} END {print s + 0}')
echo "soak figures (seed $seed, $elapsed s):"
echo "  $run_line"
echo "  $daemon_line"
echo "  $score_line"
echo "  $faults_line"
grep '^  fault ' "$out" | sed 's/^/  /' || true
echo "  floods: $floods of 8 s ($requests requests), $flood_failures failed to run"
echo "  daemon RSS: ${rss_boot} kB at 5 s, ${rss_base:-?} kB baseline (70 s), ${rss_end:-?} kB at the end, peak ${rss_peak} kB"
echo "  daemon descriptors: ${fds_boot} at 5 s, ${fds_base:-?} baseline, ${fds_end:-?} at the end"

status=0
fail() { echo "FAIL: $*"; status=1; }
[ "$sim_status" = 0 ] || fail "coxswain-sim devices exited $sim_status (see $work/sim.err)"
echo "$run_line" | grep -q 'run ended: time limit' || fail "the run did not last: $run_line"
echo "$run_line" | grep -q '(daemon exit status 0)' || fail "the daemon did not exit cleanly"
echo "$score_line" | grep -q ': completed' || fail "the course was not completed"
if grep -q '^  fault ' "$out"; then
  n=$(echo "$faults_line" | awk '{print $2}')
  of=$(echo "$faults_line" | awk '{print $4}')
  [ "$n" = "$of" ] || fail "not every fault held and recovered ($faults_line)"
fi
if grep -qE 'AddressSanitizer|LeakSanitizer|runtime error:| critical ' "$run/daemon.log"; then
  fail "the daemon's log reports a crash or a critical error"
fi
if [ -z "$rss_base" ] || [ -z "$rss_end" ]; then
  fail "the daemon's memory was not measured (did it die?)"
else
  growth=$((rss_end - rss_base))
  echo "  daemon RSS growth: ${growth} kB (limit ${max_growth_kb} kB)"
  [ "$growth" -le "$max_growth_kb" ] || fail "the daemon grew by $growth kB"
fi
if [ "$flood" = 1 ] && [ "$flood_failures" -gt 0 ]; then fail "$flood_failures floods failed"; fi
if [ "$status" = 0 ]; then
  echo "soak passed"
  [ "$keep_work" = 1 ] || rm -rf "$work"
else
  echo "soak failed; work directory kept: $work"
fi
exit "$status"
