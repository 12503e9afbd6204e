// SPDX-License-Identifier: Apache-2.0
// Cost of LidarClusterer::process per scan: on the source team's recorded run (peer/, 174 real
// scans of 1360 beams; skipped with a message when the shared test data folder is absent) and on
// synthetic scans. Each benchmark also reports the per-call median and p99 (manual percentile
// counter), since the mean hides the tail that matters for a 10 Hz loop.
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
#include "coxswain/core/angles.hpp"
#include "coxswain/perception/lidar_clusterer.hpp"
#include "peer_recording.hpp"

namespace coxswain::perception {
namespace {

struct Output {
  ObstacleList list;
  RangeProfile profile;
};

std::vector<testing::peer::PeerScan>& peer_scans() {
  static std::vector<testing::peer::PeerScan> scans;
  return scans;
}

// Runs `scans` round robin, one process() per iteration, and adds p50/p99 counters in us (and
// the input p99, see call_samples.hpp).
void run_scans(benchmark::State& state, const LidarClusterParams& params,
               const std::vector<const msg::LidarScan*>& scans) {
  LidarClusterer clusterer(params);
  auto out = std::make_unique<Output>();
  bench::CallSamples samples(scans.size());
  std::size_t next = 0;
  std::size_t segments = 0;
  for (auto _ : state) {
    const std::size_t input = next;
    const msg::LidarScan& scan = *scans[input];
    next = (next + 1) % scans.size();
    const auto t0 = std::chrono::steady_clock::now();
    clusterer.process(scan, out->list, out->profile);
    const auto t1 = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(out->list.count);
    segments += out->list.count;
    samples.add(input, std::chrono::duration<double, std::micro>(t1 - t0).count());
  }
  samples.report(state);
  state.counters["segments_per_scan"] =
      static_cast<double>(segments) /
      static_cast<double>(std::max<std::int64_t>(1, state.iterations()));
  state.SetItemsProcessed(state.iterations());
}

void BM_PeerScans(benchmark::State& state, const LidarClusterParams& params) {
  std::vector<const msg::LidarScan*> scans;
  for (const auto& s : peer_scans()) scans.push_back(s.scan.get());
  if (scans.empty()) {
    state.SkipWithError("peer recording absent (../shared/testdata/peer/)");
    return;
  }
  run_scans(state, params, scans);
}

void BM_PeerScansDefault(benchmark::State& state) {
  LidarClusterParams p;
  p.hull = HullBox{};
  BM_PeerScans(state, p);
}
void BM_PeerScansReference(benchmark::State& state) {
  BM_PeerScans(state, LidarClusterParams::reference_tricat2022());
}
// The same scans with every bearing moved by a per-scan offset (a scanner whose angles drift
// from one revolution to the next, as a real RPLIDAR's do): no bearing repeats, so the
// clusterer's per-beam cache cannot help and every return's trigonometry is computed.
void BM_PeerScansDrifting(benchmark::State& state) {
  static std::vector<std::unique_ptr<msg::LidarScan>> drifting;
  if (drifting.empty()) {
    for (std::size_t k = 0; k < peer_scans().size(); ++k) {
      auto s = std::make_unique<msg::LidarScan>(*peer_scans()[k].scan);
      const auto offset_deg = static_cast<float>(0.001 * static_cast<double>(k % 97 + 1));
      for (std::uint32_t i = 0; i < s->point_count; ++i) s->points[i].bearing_deg += offset_deg;
      drifting.push_back(std::move(s));
    }
  }
  std::vector<const msg::LidarScan*> scans;
  scans.reserve(drifting.size());
  for (const auto& s : drifting) scans.push_back(s.get());
  if (scans.empty()) {
    state.SkipWithError("peer recording absent (../shared/testdata/peer/)");
    return;
  }
  LidarClusterParams p;
  p.hull = HullBox{};
  run_scans(state, p, scans);
}

// A harbour-like scene: quay walls, a corner, buoys, 0.25 deg beams (1440 returns at most).
std::unique_ptr<msg::LidarScan> synthetic_scene() {
  struct Wall {
    double ax, ay, bx, by;
  };
  const Wall walls[] = {{8, -6, 8, 6}, {8, 6, -3, 6}, {-3, -4, 4, -4}};
  const double buoys[][3] = {{4, 1, 0.25}, {5, -2, 0.25}, {2.5, 3, 0.2}, {-6, 0.5, 0.3}};
  auto scan = std::make_unique<msg::LidarScan>();
  for (int i = 1; i <= 1440; ++i) {
    const double b = -180.0 + 0.25 * i;
    const double dx = std::cos(core::deg_to_rad(b));
    const double dy = std::sin(core::deg_to_rad(b));
    double best = 1e9;
    for (const Wall& w : walls) {
      const double ex = w.bx - w.ax;
      const double ey = w.by - w.ay;
      const double den = dx * ey - dy * ex;
      if (std::abs(den) < 1e-12) continue;
      const double t = (w.ax * ey - w.ay * ex) / den;
      const double u = (w.ax * dy - w.ay * dx) / den;
      if (t > 0 && u >= 0 && u <= 1) best = std::min(best, t);
    }
    for (const auto& c : buoys) {
      const double proj = c[0] * dx + c[1] * dy;
      const double d2 = c[0] * c[0] + c[1] * c[1] - proj * proj;
      if (proj > 0 && d2 <= c[2] * c[2]) best = std::min(best, proj - std::sqrt(c[2] * c[2] - d2));
    }
    if (best > 25.0) continue;
    // Deterministic +-1 cm ripple, like range noise.
    const double noise_m = 0.01 * std::sin(i * 12.9898);
    (void)scan->push({static_cast<float>(b), static_cast<float>(best + noise_m), 47, 0});
  }
  return scan;
}

// Worst case: kMaxPoints returns on a closed ring, one group, many pieces.
std::unique_ptr<msg::LidarScan> full_ring() {
  auto scan = std::make_unique<msg::LidarScan>();
  const auto n = static_cast<int>(msg::LidarScan::kMaxPoints);
  for (int i = 1; i <= n; ++i) {
    const double b = -180.0 + 360.0 * i / n;
    (void)scan->push(
        {static_cast<float>(b), static_cast<float>(8.0 + 0.5 * std::sin(b / 7.0)), 47, 0});
  }
  return scan;
}

void BM_SyntheticHarbour(benchmark::State& state) {
  static const auto scan = synthetic_scene();
  run_scans(state, LidarClusterParams{}, {scan.get()});
}
void BM_FullRing4096(benchmark::State& state) {
  static const auto scan = full_ring();
  run_scans(state, LidarClusterParams{}, {scan.get()});
}

BENCHMARK(BM_PeerScansDefault)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_PeerScansReference)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_PeerScansDrifting)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_SyntheticHarbour)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_FullRing4096)->Unit(benchmark::kMicrosecond);

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
        "peer recording %s absent: the BM_PeerScans* benchmarks are skipped, the "
        "synthetic ones still run\n",
        rec.string().c_str());
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
