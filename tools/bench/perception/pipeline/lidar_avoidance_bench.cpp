// SPDX-License-Identifier: Apache-2.0
// What one lidar tick costs the mission core on real data: LidarClusterer::process alone, and
// followed by Avoidance::decide for each strategy (selection, score, risk_bin), on the source
// team's recorded run (the shared test data folder/peer/, 174 scans of 1360 beams from the water).
// Each iteration is one scan, timed on its own, so the median and p99 counters are per scan: the
// mean Google Benchmark prints hides the tail that matters for a 10 Hz loop; the input p99 is
// the p99 over the scans of each scan's least time (see call_samples.hpp). Skipped, with a
// message, when the recording is absent.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <vector>

#include "common/call_samples.hpp"
#include "coxswain/guidance/avoidance.hpp"
#include "coxswain/perception/lidar_clusterer.hpp"
#include "peer_recording.hpp"

namespace coxswain::perception {
namespace {

using guidance::Avoidance;
using guidance::AvoidanceParams;
using guidance::AvoidanceStatus;
using guidance::Strategy;
using Clock = std::chrono::steady_clock;

std::vector<testing::peer::PeerScan>& peer_scans() {
  static std::vector<testing::peer::PeerScan> scans;
  return scans;
}

struct Output {
  ObstacleList list;
  RangeProfile profile;
};

double us(Clock::duration d) { return std::chrono::duration<double, std::micro>(d).count(); }

// The clusterer as the daemon runs it, except the hull box: their boat is not ours and their
// lidar saw nothing of its own hull in this run (the same choice as lidar_peer_test).
LidarClusterParams peer_params() {
  LidarClusterParams p;
  p.hull = HullBox{};
  return p;
}

// state.range(0): -1 = clustering alone, else the Strategy (+ 10: with the swept hull, as the
// obstacle course runs it). Goal dead ahead, so every obstacle
// near the bow is in the way; `now` is the scan's own stamp so the hold time sees real spacing.
void BM_PeerLidarTick(benchmark::State& state) {
  const auto& scans = peer_scans();
  if (scans.empty()) {
    state.SkipWithError("peer recording absent (../shared/testdata/peer/): nothing to measure");
    return;
  }
  const bool with_avoidance = state.range(0) >= 0;
  AvoidanceParams ap;
  if (with_avoidance) {
    ap.strategy = static_cast<Strategy>(state.range(0) % 10);
    ap.sweep_enabled = state.range(0) >= 10;
  }
  auto avoidance = std::make_unique<Avoidance>(*Avoidance::create(ap));
  LidarClusterer clusterer(peer_params());
  auto out = std::make_unique<Output>();

  bench::CallSamples total_us(scans.size());
  bench::CallSamples cluster_us(scans.size());
  bench::CallSamples avoid_us(scans.size());
  std::size_t next = 0;
  std::int64_t segments = 0;
  std::int64_t steering_away = 0;  // decisions that did not steer straight at the goal
  for (auto _ : state) {
    const std::size_t input = next;
    const msg::LidarScan& scan = *scans[input].scan;
    if (input == 0) avoidance->reset();  // the replay starts over: a new leg
    next = (next + 1) % scans.size();
    const auto t0 = Clock::now();
    clusterer.process(scan, out->list, out->profile);
    const auto t1 = Clock::now();
    auto t2 = t1;
    if (with_avoidance) {
      const auto d = avoidance->decide(out->list, 0.0, scan.stamp_ns);
      t2 = Clock::now();
      benchmark::DoNotOptimize(d.bearing_body_deg);
      steering_away += d.status != AvoidanceStatus::kClear ? 1 : 0;
    }
    benchmark::DoNotOptimize(out->list.count);
    segments += out->list.count;
    total_us.add(input, us(t2 - t0));
    cluster_us.add(input, us(t1 - t0));
    if (with_avoidance) avoid_us.add(input, us(t2 - t1));
  }
  total_us.report(state);
  if (with_avoidance) {
    cluster_us.report(state, "cluster_");
    avoid_us.report(state, "avoid_");
    state.counters["not_clear_pct"] =
        100.0 * static_cast<double>(steering_away) / static_cast<double>(state.iterations());
  }
  state.counters["segments_per_scan"] =
      static_cast<double>(segments) / static_cast<double>(state.iterations());
  state.SetLabel(with_avoidance ? std::string("clustering + ") + to_string(ap.strategy) +
                                      (ap.sweep_enabled ? " + swept hull" : "")
                                : std::string("clustering alone"));
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_PeerLidarTick)
    ->ArgName("strategy")
    ->Arg(-1)
    ->Arg(static_cast<int>(Strategy::kSelection))
    ->Arg(static_cast<int>(Strategy::kScore))
    ->Arg(static_cast<int>(Strategy::kRiskBin))
    ->Arg(10 + static_cast<int>(Strategy::kScore))
    ->Arg(10 + static_cast<int>(Strategy::kSelection))
    ->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace coxswain::perception

int main(int argc, char** argv) {
  namespace fs = std::filesystem;
  const char* env = std::getenv("COXSWAIN_SHARED_TESTDATA");
  const fs::path dir = env != nullptr ? env : COXSWAIN_BENCH_TESTDATA;
  const fs::path rec = dir / "peer/tricat221-0223-scans.jsonl";
  if (fs::exists(rec)) {
    coxswain::perception::peer_scans() = coxswain::testing::peer::load_peer_recording(rec);
    std::printf("peer recording: %zu scans from %s\n", coxswain::perception::peer_scans().size(),
                rec.string().c_str());
  } else {
    std::printf(
        "peer recording %s absent (set COXSWAIN_SHARED_TESTDATA or put ../shared/testdata beside "
        "the clone): every benchmark here is skipped\n",
        rec.string().c_str());
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
