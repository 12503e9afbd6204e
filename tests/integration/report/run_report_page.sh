#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# CTest driver: records a judged simulator run on a course where the global planner plans,
# writes its report and drives the page in headless Chromium (report_page_test.mjs).
# Exit 77 (reported as skipped) when node, npm or chromium is missing or npm cannot install.
set -euo pipefail
coxswain=$1
sim=$2
src=$3
work=$4
config=$5
if ! command -v chromium >/dev/null 2>&1; then
  echo "SKIP: chromium is not installed (apt-get install chromium): the report page was not driven"
  exit 77
fi
# shellcheck source=../../support/npm_clients.sh
source "$src/../../support/npm_clients.sh"
# Without install scripts puppeteer-core downloads no browser: it drives the system's chromium.
install_npm_clients "$src" "$work/node" puppeteer-core "the report page test"
cp "$src/report_page_test.mjs" "$work/node/"
rm -rf "$work/run"
mkdir -p "$work/run"
status=0
"$sim" run --course "$config/courses/kaboat2022_obstacle_preliminary.yaml" \
  --mission "$config/missions/obstacle_course.yaml" --boat "$config/boat.yaml" \
  --devices "$config/devices.yaml" --seed 1 --max-time 90 \
  --record "$work/run/run.mcap" --out "$work/run" || status=$?
if [ "$status" -gt 1 ] || [ ! -s "$work/run/run.mcap" ]; then
  echo "FAIL: coxswain-sim run exited $status without a recording"
  exit 1
fi
"$coxswain" report "$work/run/run.mcap" -o "$work/run/report.html"
echo '{"score": true, "calibration": true, "plan": true}' >"$work/run/expect.json"
CHROMIUM="$(command -v chromium)" node "$work/node/report_page_test.mjs" "$work/run/report.html" \
  "$work/run/expect.json"
