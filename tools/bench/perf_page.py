#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Runs the speed benchmarks with JSON output and writes docs/performance.md.

Each row: what is measured, the median and p99 of single calls (wall clock, the benchmark's own
per-call samples) and the mean CPU time, the target, the exact command, and the load average
when it ran (the machine is shared: ratios between rows mean more than absolutes under load).

  tools/bench/perf_page.py [--build build] [--out docs/performance.md] [--min-time 1]

The recorded lidar scans come from the shared test data folder (COXSWAIN_SHARED_TESTDATA, else
../shared/testdata beside the clone); without them those rows say "skipped".
"""
import argparse
import datetime
import json
import os
import platform
import shlex
import subprocess
import sys
import tempfile

# (benchmark program relative to the build folder, filter, row label, target text,
#  target check: (counter, limit_us) pairs, all must hold)
ROWS = [
    ("tools/bench/perception/lidar/bench_lidar_clustering", "BM_PeerScansDefault$",
     "clustering per recorded scan (peer, default mode)", "median <= 8 us",
     [("p50_us", 8.0)]),
    ("tools/bench/perception/lidar/bench_lidar_clustering", "BM_PeerScansDrifting$",
     "clustering per recorded scan, bearings drifting scan to scan (no beam cache hits)",
     "median <= 8 us", [("p50_us", 8.0)]),
    ("tools/bench/perception/lidar/bench_lidar_clustering", "BM_PeerScansReference$",
     "clustering per recorded scan (peer, the source team's reference mode)", "-", []),
    ("tools/bench/perception/pipeline/bench_lidar_avoidance", "BM_PeerLidarTick/strategy:11$",
     "clustering + avoidance as shipped (score + swept hull), per recorded scan",
     "median <= 16 us, p99 <= 40 us", [("p50_us", 16.0), ("p99_us", 40.0)]),
    ("tools/bench/perception/pipeline/bench_lidar_avoidance", "BM_PeerLidarTick/strategy:1$",
     "clustering + avoidance, score without the swept hull", "-", []),
    ("tools/bench/mission/bench_mission", "BM_StepWithNewScan/shipped:1/planner:0$",
     "mission step with a new scan (3600 returns), shipped obstacle course, planner off",
     "p99 <= 50 us", [("p99_us", 50.0)]),
    ("tools/bench/mission/bench_mission", "BM_StepBetweenScans/shipped:1/planner:0$",
     "mission step between scans, shipped obstacle course, planner off", "p99 <= 5 us",
     [("p99_us", 5.0)]),
    ("tools/bench/mission/bench_mission", "BM_StepWithNewScan/shipped:1/planner:1$",
     "mission step with a new scan, lidar map and planner on", "p99 <= 50 us",
     [("p99_us", 50.0)]),
    ("tools/bench/mission/bench_mission", "BM_StepBetweenScans/shipped:1/planner:1$",
     "mission step between scans, lidar map and planner on (replans included)", "p99 <= 5 us",
     [("p99_us", 5.0)]),
]


def fmt_us(v):
    if v is None:
        return "-"
    return f"{v:.1f} us" if v < 1000 else f"{v / 1000:.2f} ms"


def run_row(build, prog, flt, min_time):
    exe = os.path.join(build, prog)
    if not os.path.exists(exe):
        return None, f"{prog} not built", None
    with tempfile.NamedTemporaryFile(suffix=".json", delete=False) as f:
        out = f.name
    cmd = [exe, f"--benchmark_filter={flt}", f"--benchmark_min_time={min_time}",
           "--benchmark_format=json", f"--benchmark_out={out}"]
    load = os.getloadavg()
    proc = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    try:
        with open(out) as f:
            data = json.load(f)
    except (OSError, ValueError):
        return None, f"no JSON output ({proc.stderr.strip()[:200]})", load
    finally:
        os.unlink(out)
    benches = [b for b in data.get("benchmarks", []) if b.get("run_type") == "iteration"]
    shown = [exe, f"--benchmark_filter='{flt}'", f"--benchmark_min_time={min_time}",
             "--benchmark_format=json"]
    if not benches:
        return None, "no result", load
    b = benches[0]
    if b.get("error_occurred"):
        return None, "skipped: " + b.get("error_message", ""), load
    b["_command"] = " ".join(shlex.quote(c) if "'" not in c else c for c in shown)
    return b, None, load


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default="build", help="build folder (default: build)")
    ap.add_argument("--out", default="docs/performance.md")
    ap.add_argument("--min-time", default="1", help="--benchmark_min_time per row, seconds")
    args = ap.parse_args()

    lines = []
    met = 0
    checked = 0
    for prog, flt, label, target, checks in ROWS:
        b, err, load = run_row(args.build, prog, flt, args.min_time)
        load_txt = "-" if load is None else " / ".join(f"{x:.2f}" for x in load)
        if b is None:
            lines.append(f"| {label} | {err} | - | {target} | - | `{prog}` | {load_txt} |")
            print(f"{label}: {err}", file=sys.stderr)
            continue
        p50 = b.get("p50_us")
        p99 = b.get("p99_us")
        cpu = b.get("cpu_time")
        unit = b.get("time_unit", "ns")
        cpu_us = cpu if unit == "us" else cpu / 1000.0 if unit == "ns" else cpu * 1000.0
        verdict = "-"
        if checks:
            ok = all(b.get(k) is not None and b[k] <= lim for k, lim in checks)
            verdict = "met" if ok else "not met"
            checked += 1
            met += 1 if ok else 0
        lines.append(f"| {label} | {fmt_us(p50)} / {fmt_us(p99)} | {fmt_us(cpu_us)} | {target} | "
                     f"{verdict} | `{b['_command']}` | {load_txt} |")
        print(f"{label}: p50 {fmt_us(p50)} p99 {fmt_us(p99)} cpu {fmt_us(cpu_us)} ({verdict}), "
              f"load {load_txt}", file=sys.stderr)

    now = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    cpu_name = platform.processor() or platform.machine()
    page = [
        "<!-- Generated by tools/bench/perf_page.py; do not edit by hand. -->",
        "# Performance",
        "",
        f"Measured {now} on {os.cpu_count()} cores ({cpu_name}), build `{args.build}` "
        "(RelWithDebInfo). Median and p99 are of single calls timed one by one (wall clock); "
        "CPU is Google Benchmark's mean CPU time per call. The load average (1 / 5 / 15 min) is "
        "taken as each row starts: on a shared machine a loaded row's wall-clock tail is the "
        "neighbours' as much as ours.",
        "",
        f"Targets met: {met} of {checked} rows with a target.",
        "",
        "| what | median / p99 | CPU (mean) | target | | command | load average |",
        "| --- | --- | --- | --- | --- | --- | --- |",
        *lines,
        "",
        "Regenerate: `tools/bench/perf_page.py --build build` (after building the `bench_*` "
        "targets); the recorded scans are the shared test data folder's `peer/` run.",
        "",
    ]
    with open(args.out, "w") as f:
        f.write("\n".join(page))
    print(f"wrote {args.out}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
