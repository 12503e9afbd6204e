#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The daemon's footprint at nominal sensor load: devices mode (the unmodified daemon against the
# device emulators, in real time) on the 2026 course, the daemon's CPU and memory read from /proc
# while it runs, in three arrangements: no camera and no recording; no camera, recording on (the
# recorder's share is the difference); the camera at 30 fps, recording on. Beside each row, the
# CPU of the recorder's own threads (named cx-rec-*): the part of the share that is not noise.
# Prints a table, and with --json FILE writes the rows for tools/bench/perf_page.py.
#
#   tools/bench/daemon_load.sh [--build build] [--warmup S] [--measure S] [--json FILE]
#
# CPU is the daemon's own user + system time over the measured window divided by the window (100%
# = one core), from /proc/PID/stat. RSS is the largest resident set seen (VmRSS, sampled every
# second) and the kernel's high-water mark (VmHWM). The recording's size is its growth over the
# window, scaled to 10 minutes. The world runs in real time, so a row takes warmup + measure
# seconds; a loaded machine slows the emulators' threads, not the daemon's accounting.
set -euo pipefail
cd "$(dirname "$0")/../.."
build=build
warmup_s=20
measure_s=60
json_out=""
while [ $# -gt 0 ]; do
  case "$1" in
    --build) build="$2"; shift 2 ;;
    --warmup) warmup_s="$2"; shift 2 ;;
    --measure) measure_s="$2"; shift 2 ;;
    --json) json_out="$2"; shift 2 ;;
    -h|--help) sed -n '3,16p' "$0"; exit 0 ;;
    *) echo "daemon_load: unknown option $1" >&2; exit 2 ;;
  esac
done
sim="$build/tools/sim/app/coxswain-sim"
daemon="$build/src/app/coxswain"
for f in "$sim" "$daemon"; do
  [ -x "$f" ] || { echo "daemon_load: $f not built" >&2; exit 2; }
done
sim=$(realpath "$sim")
daemon=$(realpath "$daemon")
work=$(mktemp -d "${TMPDIR:-/tmp}/daemon_load.XXXXXX")
[ -n "${DAEMON_LOAD_KEEP:-}" ] || trap 'rm -rf "$work"' EXIT
hz=$(getconf CLK_TCK)

# The daemon devices mode starts, through a wrapper that adjusts its arguments: no camera (the
# devices file's camera following an empty folder, so no frame ever comes) and/or no recording
# (--no-record).
make_wrapper() {  # name camera(0/1) record(0/1)
  local w="$work/$1.sh"
  cat > "$w" <<EOF
#!/usr/bin/env bash
args=()
while [ \$# -gt 0 ]; do
  if [ "\$1" = "--devices" ] && [ "$2" = 0 ]; then
    mkdir -p "$work/no_frames"
    sed 's|source: "follow:[^"]*"|source: "follow:$work/no_frames"|' "\$2" > "\$2.nocamera.yaml"
    args+=("\$1" "\$2.nocamera.yaml"); shift 2; continue
  fi
  args+=("\$1"); shift
done
[ "$3" = 0 ] && args+=("--no-record")
exec "$daemon" "\${args[@]}"
EOF
  chmod +x "$w"
  echo "$w"
}

# A sensors file whose camera renders at 30 frames per second.
sensors30="$work/sensors30.yaml"
sed 's/^\(    rate_hz:\) *10.0\( *# frames rendered.*\)$/\1 30.0\2/' config/sim/sensors.yaml > "$sensors30"
grep -q 'rate_hz: 30.0 *# frames rendered' "$sensors30" ||
  { echo "daemon_load: could not set the camera to 30 fps in a copy of config/sim/sensors.yaml" >&2; exit 1; }

ticks_of() { awk '{print $14 + $15}' "/proc/$1/stat"; }
# The recorder's own threads (named cx-rec-*, no spaces, so stat's fields split as for the
# process): their user + system ticks summed; a thread gone between two reads counts 0.
recorder_ticks_of() {
  local sum=0 t ticks
  for t in /proc/"$1"/task/*; do
    case "$(cat "$t/comm" 2>/dev/null)" in
      cx-rec-*)
        ticks=$(awk '{print $14 + $15}' "$t/stat" 2>/dev/null || true)
        sum=$((sum + ${ticks:-0})) ;;
    esac
  done
  echo "$sum"
}
kb_of() { awk -v k="$2" '$1 == k":" {print $2}' "/proc/$1/status"; }

rows=()
run_row() {  # label camera record
  local label="$1" camera="$2" record="$3"
  local wrapper run_dir sensors_args=()
  wrapper=$(make_wrapper "w$camera$record" "$camera" "$record")
  run_dir="$work/run$camera$record"
  [ "$camera" = 1 ] && sensors_args=(--sensors "$sensors30")
  local total=$((warmup_s + measure_s + 30))
  "$sim" devices --course config/courses/kaboat2026.yaml --seed 1 --run-dir "$run_dir" \
    --daemon "$wrapper" --time-limit "$total" --run-past-finish --no-progress --quiet \
    "${sensors_args[@]}" > "$work/sim$camera$record.log" 2>&1 &
  local sim_pid=$!
  local pid=""
  for _ in $(seq 1 100); do
    pid=$(pgrep -P "$sim_pid" -x coxswain || true)
    [ -n "$pid" ] && break
    sleep 0.2
  done
  [ -n "$pid" ] || { echo "daemon_load: no daemon under coxswain-sim" >&2; cat "$work/sim$camera$record.log" >&2; exit 1; }
  sleep "$warmup_s"
  local mcap
  mcap=$(find "$run_dir" -name '*.mcap' 2>/dev/null | head -1)
  local size0=0
  [ -n "$mcap" ] && size0=$(stat -c %s "$mcap")
  local t0 c0 r0 rss_max=0 rss
  t0=$(date +%s.%N)
  c0=$(ticks_of "$pid")
  r0=$(recorder_ticks_of "$pid")
  for _ in $(seq 1 "$measure_s"); do
    sleep 1
    rss=$(kb_of "$pid" VmRSS)
    [ "$rss" -gt "$rss_max" ] && rss_max=$rss
  done
  local c1 r1 t1 hwm size1=0
  c1=$(ticks_of "$pid")
  r1=$(recorder_ticks_of "$pid")
  t1=$(date +%s.%N)
  hwm=$(kb_of "$pid" VmHWM)
  [ -z "$mcap" ] && mcap=$(find "$run_dir" -name '*.mcap' 2>/dev/null | head -1)
  [ -n "$mcap" ] && size1=$(stat -c %s "$mcap")
  kill "$sim_pid" 2>/dev/null || true
  wait "$sim_pid" 2>/dev/null || true
  local cpu rec_cpu rss_mb hwm_mb mb_per_10min
  cpu=$(awk -v c="$((c1 - c0))" -v hz="$hz" -v t0="$t0" -v t1="$t1" 'BEGIN {printf "%.2f", 100 * c / hz / (t1 - t0)}')
  rec_cpu=$(awk -v c="$((r1 - r0))" -v hz="$hz" -v t0="$t0" -v t1="$t1" 'BEGIN {printf "%.2f", 100 * c / hz / (t1 - t0)}')
  rss_mb=$(awk -v k="$rss_max" 'BEGIN {printf "%.1f", k / 1024}')
  hwm_mb=$(awk -v k="$hwm" 'BEGIN {printf "%.1f", k / 1024}')
  mb_per_10min=$(awk -v d="$((size1 - size0))" -v t0="$t0" -v t1="$t1" -v r="$record" 'BEGIN {if (r == 0) print "-"; else printf "%.1f", d / (t1 - t0) * 600 / 1e6}')
  rows+=("$label|$cpu|$rss_mb|$hwm_mb|$mb_per_10min|$rec_cpu")
  echo "daemon_load: $label: cpu ${cpu}% (recorder threads ${rec_cpu}%), rss ${rss_mb} MB (high-water ${hwm_mb} MB), recording ${mb_per_10min} MB/10 min" >&2
}

load_before=$(cut -d' ' -f1-3 /proc/loadavg)
run_row "no camera, recording off" 0 0
run_row "no camera, recording on" 0 1
run_row "camera 30 fps, recording on" 1 1
load_after=$(cut -d' ' -f1-3 /proc/loadavg)

echo "| arrangement | daemon CPU (% of a core) | of it the recorder's threads | RSS max (MB) | RSS high-water (MB) | recording (MB per 10 min) |"
echo "| --- | --- | --- | --- | --- | --- |"
for r in "${rows[@]}"; do
  IFS='|' read -r label cpu rss hwm mb rec <<< "$r"
  echo "| $label | $cpu | $rec | $rss | $hwm | $mb |"
done
IFS='|' read -r _ cpu_off _ _ _ _ <<< "${rows[0]}"
IFS='|' read -r _ cpu_on _ _ _ rec_on <<< "${rows[1]}"
share=$(awk -v a="$cpu_on" -v b="$cpu_off" 'BEGIN {printf "%.2f", a - b}')
echo
echo "Recorder's share (recording on minus off, no camera): $share % of a core; its own threads: $rec_on %. Load average before / after: $load_before / $load_after. Window: ${measure_s} s after ${warmup_s} s."

if [ -n "$json_out" ]; then
  {
    echo "{\"load_before\": \"$load_before\", \"load_after\": \"$load_after\", \"measure_s\": $measure_s, \"warmup_s\": $warmup_s, \"recorder_share_pct\": $share, \"recorder_threads_pct\": $rec_on, \"rows\": ["
    sep=""
    for r in "${rows[@]}"; do
      IFS='|' read -r label cpu rss hwm mb rec <<< "$r"
      [ "$mb" = "-" ] && mb=null
      echo "$sep{\"label\": \"$label\", \"cpu_pct\": $cpu, \"recorder_threads_pct\": $rec, \"rss_mb\": $rss, \"rss_hwm_mb\": $hwm, \"recording_mb_per_10min\": $mb}"
      sep=","
    done
    echo "]}"
  } > "$json_out"
fi
