// SPDX-License-Identifier: Apache-2.0
// Flight recorder costs.
//  * BM_RawRecording/<kind>: raw device bytes through on_raw (512-byte reads), the queue, the
//    writer thread, zstd chunks and write(2) to a file in $TMPDIR, fdatasync every chunk (1 s):
//    bytes/s recorded end to end (each iteration queues 2 MiB and waits until all of it is in the
//    writer). kind 0 = random bytes (zstd's worst case), 1 = RPLIDAR-like node stream.
//  * BM_RecordTick/<viz>: the tick thread's cost of Recorder::record_tick with a full Snapshot
//    (encode into the queue slot, no allocation); viz 1 also copies the TickViz.
//  * BM_EncodeTick: the encoder alone.
//  * BM_Crc32: the CRC the writer runs over every byte.
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <memory>
#include <random>
#include <thread>
#include <vector>

#include "coxswain/record/crc32.hpp"
#include "coxswain/record/layouts.hpp"
#include "coxswain/record/proto_codec.hpp"
#include "coxswain/record/recorder.hpp"

namespace {

using namespace coxswain;
namespace fs = std::filesystem;

fs::path bench_path(const char* name) {
  return fs::temp_directory_path() /
         ("coxswain_bench_" + std::to_string(::getpid()) + "_" + name + ".mcap");
}

std::vector<std::uint8_t> stream(int kind, std::size_t n) {
  std::vector<std::uint8_t> v(n);
  std::mt19937 rng(1);
  if (kind == 0) {
    for (auto& b : v) b = static_cast<std::uint8_t>(rng());
  } else {
    // 5-byte standard nodes: quality/sync, angle rising, distance wandering.
    for (std::size_t i = 0; i + 5 <= n; i += 5) {
      const auto angle = static_cast<std::uint16_t>(((i / 5) % 720) * 32 << 1 | 1);
      const auto dist = static_cast<std::uint16_t>(4000 + (rng() % 200));
      v[i] = static_cast<std::uint8_t>(0x3C << 2 | ((i / 5) % 720 == 0 ? 1 : 2));
      v[i + 1] = static_cast<std::uint8_t>(angle);
      v[i + 2] = static_cast<std::uint8_t>(angle >> 8);
      v[i + 3] = static_cast<std::uint8_t>(dist);
      v[i + 4] = static_cast<std::uint8_t>(dist >> 8);
    }
  }
  return v;
}

void BM_RawRecording(benchmark::State& state) {
  const int kind = static_cast<int>(state.range(0));
  constexpr std::size_t kRead = 512;
  constexpr std::size_t kBatch = 2U << 20U;
  const auto bytes = stream(kind, kBatch);
  core::SteadyClock clock;
  record::RecorderOptions o;
  o.path = bench_path("raw");
  o.raw_queue_slots = 8192;  // holds a whole batch: nothing is dropped
  record::Recorder rec(o, nullptr, clock);
  if (!rec.start()) {
    state.SkipWithError("cannot start the recorder");
    return;
  }
  std::uint64_t queued = 0;
  for (auto _ : state) {
    for (std::size_t at = 0; at < bytes.size(); at += kRead) {
      rec.on_raw(msg::DeviceId::kLidar, drivers::RawDirection::kFromDevice,
                 static_cast<core::TimeNs>(queued + at),
                 std::span<const std::uint8_t>(bytes).subspan(at, kRead));
    }
    queued += bytes.size();
    while (rec.stats().raw_bytes + rec.stats()[record::RecordChannel::kRawLidar].dropped * kRead <
           queued) {
      std::this_thread::yield();
    }
  }
  rec.stop();
  const auto st = rec.stats();
  state.SetBytesProcessed(static_cast<std::int64_t>(st.raw_bytes));
  state.counters["dropped"] = static_cast<double>(st.total_dropped());
  state.counters["file_MB"] = static_cast<double>(st.file_bytes) / 1e6;
  state.counters["ratio"] = static_cast<double>(st.raw_bytes) /
                            static_cast<double>(std::max<std::uint64_t>(1, st.file_bytes));
  fs::remove(o.path);
}
BENCHMARK(BM_RawRecording)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

std::unique_ptr<core::Snapshot> full_snapshot() {
  auto snap = std::make_unique<core::Snapshot>();
  snap->lidar.sequence = 10;
  snap->lidar.value.point_count = 2000;
  snap->imu.sequence = 100;
  snap->gnss.sequence = 20;
  for (std::size_t i = 0; i < 8; ++i) {
    (void)snap->camera.value.push({msg::Colour::kRed, msg::Shape::kBuoy, 1, 2, 3, 4, 5, 6, 0.5F});
  }
  for (auto& h : snap->health) {
    h.sequence = 5;
    h.value.set_detail("running, 10.0 Hz, no errors in the last window");
  }
  return snap;
}

void BM_RecordTick(benchmark::State& state) {
  const bool with_viz = state.range(0) != 0;
  core::SteadyClock clock;
  record::RecorderOptions o;
  o.path = bench_path("tick");
  o.tick_queue_slots = 8192;
  record::Recorder rec(o, nullptr, clock);
  if (!rec.start()) {
    state.SkipWithError("cannot start the recorder");
    return;
  }
  auto snap = full_snapshot();
  record::TickViz viz;
  viz.pose_valid = true;
  viz.obstacle_count = 10;
  record::TickInput in;
  in.snapshot = snap.get();
  in.state_path = "ACTIVE:COURSE2:AVOIDING";
  in.viz = with_viz ? &viz : nullptr;
  for (auto _ : state) {
    ++in.tick_index;
    benchmark::DoNotOptimize(rec.record_tick(in));
  }
  rec.stop();
  state.counters["dropped"] = static_cast<double>(rec.stats().total_dropped());
  fs::remove(o.path);
}
// A bounded number of ticks (the queue holds them all), so the cost measured is the producer's.
BENCHMARK(BM_RecordTick)->Arg(0)->Arg(1)->Iterations(4000)->Unit(benchmark::kMicrosecond);

// What the tick thread pays per tick: the protobuf tick the recorder writes, and the legacy
// packed layout for comparison.
void BM_EncodeTick(benchmark::State& state) {
  auto snap = full_snapshot();
  std::vector<std::uint8_t> buf(record::proto::kMaxTickBytes);
  msg::ActuatorCommand cmd;
  for (auto _ : state) {
    benchmark::DoNotOptimize(record::proto::encode_tick(buf, 1, 2, *snap, cmd, "ACTIVE:COURSE2"));
  }
}
BENCHMARK(BM_EncodeTick);

void BM_EncodeTickLegacyLayout(benchmark::State& state) {
  auto snap = full_snapshot();
  std::vector<std::uint8_t> buf(record::kMaxTickBytes);
  msg::ActuatorCommand cmd;
  for (auto _ : state) {
    benchmark::DoNotOptimize(record::encode_tick(buf, 1, 2, *snap, cmd, "ACTIVE:COURSE2"));
  }
}
BENCHMARK(BM_EncodeTickLegacyLayout);

void BM_Crc32(benchmark::State& state) {
  const auto bytes = stream(0, 1U << 20U);
  for (auto _ : state) benchmark::DoNotOptimize(record::crc32(bytes));
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) *
                          static_cast<std::int64_t>(bytes.size()));
}
BENCHMARK(BM_Crc32);

}  // namespace
