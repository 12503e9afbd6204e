#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The main job: set up, build, and run the daemon on the shipped config (Ctrl-C stops it cleanly).
# Extra arguments go to `coxswain run`, e.g. scripts/run.sh --run-for-s 10
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
exec build/src/app/coxswain --log-dir runs run "$@"
