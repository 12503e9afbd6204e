#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The main job: set up and build, then sail the default 2026 course (config/courses/kaboat2026.yaml
# with config/missions/kaboat2026.yaml) in the simulator's devices mode: every sensor is its device
# emulator on a pseudo-terminal, the camera a frame directory, and the UNMODIFIED coxswain daemon
# runs against them in real time. The run ends with the score (result.json and track.svg in the
# run directory it names). Ctrl-C stops it cleanly (daemon stopped, ptys removed, score so far).
#   scripts/run.sh [coxswain-sim devices options]   e.g. --seed 3 --time-limit 120 --quiet
#   scripts/run.sh --daemon-only [coxswain run options]
#       just the daemon on the real hardware (config/devices.yaml), e.g. on the boat's NUC;
#       e.g. scripts/run.sh --daemon-only --run-for-s 10
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
if [ "${1:-}" = "--daemon-only" ]; then
  shift
  exec build/src/app/coxswain --log-dir runs run "$@"
fi
exec build/tools/sim/app/coxswain-sim devices \
  --course config/courses/kaboat2026.yaml \
  --mission config/missions/kaboat2026.yaml "$@"
