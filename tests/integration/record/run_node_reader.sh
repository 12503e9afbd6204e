#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# CTest driver: installs the pinned npm test clients (package-lock.json) under the build tree,
# writes a recording with every channel and opens it with @mcap/core (read_mcap.mjs); then does the
# same with a lockstep simulator run's recording (`coxswain-sim run --record`, realistic sensors),
# its message counts checked against the counters the run wrote in its result.json; then a
# devices-mode run's recording (the real daemon on emulated serial devices).
# Exit 77 (reported as skipped) when node/npm are missing or the npm registry is unreachable.
set -euo pipefail
writer=$1
src=$2
work=$3
sim=$4
config=$5
layout="$config/foxglove/layout.json"  # the shipped Foxglove layout
# shellcheck source=../../support/npm_clients.sh
source "$src/../../support/npm_clients.sh"
install_npm_clients "$src" "$work/node" @mcap/core "the @mcap/core check"
cp "$src/read_mcap.mjs" "$work/node/"
"$writer" "$work/sample.mcap" "$work/expected.json"
node "$work/node/read_mcap.mjs" "$work/sample.mcap" "$work/expected.json"

# A simulator run (20 s of the 2022 hopping course; it does not finish, so exit 1 is expected).
rm -rf "$work/sim"
mkdir -p "$work/sim"
status=0
"$sim" run --course "$config/courses/kaboat2022_hopping.yaml" \
  --mission "$config/missions/hopping.yaml" --boat "$config/boat.yaml" \
  --devices "$config/devices.yaml" --seed 1 --max-time 20 \
  --record "$work/sim/run.mcap" --out "$work/sim" || status=$?
if [ "$status" -gt 1 ] || [ ! -s "$work/sim/result.json" ]; then
  echo "FAIL: coxswain-sim run exited $status without a result.json"
  exit 1
fi
node -e '
const fs = require("fs");
const r = JSON.parse(fs.readFileSync(process.argv[1], "utf8"));
if (!r.recording) { console.error("FAIL: result.json has no recording counters"); process.exit(1); }
if (r.recording.failed) { console.error("FAIL: " + r.recording.error); process.exit(1); }
for (const [topic, n] of Object.entries(r.recording.dropped)) {
  if (n !== 0) { console.error(`FAIL: the simulator dropped ${n} messages on ${topic}`); process.exit(1); }
}
fs.writeFileSync(process.argv[2], JSON.stringify({ written: r.recording.written,
  must_have: ["/tick", "/lidar", "/imu", "/gnss", "/operator", "/viz/scene", "/tf", "/viz/scan",
              "/viz/fix", "/viz/map", "/map/geojson"] }));
' "$work/sim/result.json" "$work/sim/expected.json"
node "$work/node/read_mcap.mjs" "$work/sim/run.mcap" "$work/sim/expected.json"

# Devices mode: the daemon itself on pseudo-terminals, 20 s of the 2026 course (start-up, GNSS
# calibration, sailing); every channel the daemon records must decode.
rm -rf "$work/devices"
"$sim" devices --course "$config/courses/kaboat2026.yaml" \
  --mission "$config/missions/kaboat2026.yaml" --run-dir "$work/devices" --time-limit 20 \
  --quiet --no-progress >"$work/devices.log" 2>&1 || true
mcap=$(find "$work/devices/daemon" -name run.mcap 2>/dev/null | head -n 1)
if [ -z "$mcap" ]; then
  cat "$work/devices.log"
  echo "FAIL: the devices-mode daemon wrote no recording under $work/devices/daemon"
  exit 1
fi
echo '{"must_have": ["/tick", "/lidar", "/imu", "/gnss", "/arduino", "/health", "/raw/lidar",
  "/raw/imu", "/raw/gnss", "/raw/arduino", "/viz/scene", "/tf", "/log", "/viz/map", "/map/geojson",
  "/camera/image", "/camera/annotations"],
  "layout": "'"$layout"'"}' >"$work/devices/expected.json"
node "$work/node/read_mcap.mjs" "$mcap" "$work/devices/expected.json"
