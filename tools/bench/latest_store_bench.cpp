// SPDX-License-Identifier: Apache-2.0
// Cost of publishing into and snapshotting the LatestStore, the per-tick data path.
#include <benchmark/benchmark.h>

#include <memory>

#include "coxswain/core/latest_store.hpp"

namespace coxswain::core {
namespace {

void BM_PublishImu(benchmark::State& state) {
  auto store = std::make_unique<LatestStore>();
  msg::ImuSample imu;
  TimeNs t = 0;
  for (auto _ : state) {
    imu.heading_deg += 0.1;
    store->imu.publish(imu, ++t);
  }
  state.SetBytesProcessed(state.iterations() * static_cast<int64_t>(sizeof(msg::ImuSample)));
}
BENCHMARK(BM_PublishImu);

void BM_PublishFullScan(benchmark::State& state) {
  auto store = std::make_unique<LatestStore>();
  auto scan = std::make_unique<msg::LidarScan>();
  for (std::size_t i = 0; i < msg::LidarScan::kMaxPoints; ++i) {
    (void)scan->push({static_cast<float>(i) * 0.1F, 3.0F, 10, 0});
  }
  TimeNs t = 0;
  for (auto _ : state) store->lidar.publish(*scan, ++t);
  state.SetBytesProcessed(state.iterations() * static_cast<int64_t>(sizeof(msg::LidarScan)));
}
BENCHMARK(BM_PublishFullScan);

void BM_ReadImu(benchmark::State& state) {
  auto store = std::make_unique<LatestStore>();
  store->imu.publish(msg::ImuSample{}, 1);
  Sample<msg::ImuSample> s;
  for (auto _ : state) {
    store->imu.read(s);
    benchmark::DoNotOptimize(s);
  }
}
BENCHMARK(BM_ReadImu);

void BM_Snapshot(benchmark::State& state) {
  auto store = std::make_unique<LatestStore>();
  auto snap = std::make_unique<Snapshot>();
  store->lidar.publish(msg::LidarScan{}, 1);
  store->imu.publish(msg::ImuSample{}, 1);
  store->gnss.publish(msg::GnssFix{}, 1);
  for (auto _ : state) {
    store->snapshot(*snap);
    benchmark::DoNotOptimize(snap.get());
  }
  state.SetBytesProcessed(state.iterations() * static_cast<int64_t>(sizeof(Snapshot)));
}
BENCHMARK(BM_Snapshot);

}  // namespace
}  // namespace coxswain::core
