#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Set up, build (warnings are errors) and run the whole test suite. CI runs exactly this.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
ctest --test-dir build --output-on-failure -j "${COXSWAIN_JOBS:-2}"
