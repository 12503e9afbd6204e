// SPDX-License-Identifier: Apache-2.0
// RPLIDAR codec costs: decode throughput for standard-node and express-capsule streams, and the
// per-revolution cost of assembling a 1440-point scan.
#include <benchmark/benchmark.h>

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "coxswain/drivers/rplidar/answer_encoder.hpp"
#include "coxswain/drivers/rplidar/codec.hpp"
#include "coxswain/drivers/rplidar/scan_assembler.hpp"

namespace coxswain::drivers::rplidar {
namespace {

std::vector<std::uint8_t> standard_stream(std::size_t nodes) {
  std::vector<std::uint8_t> s;
  for (std::size_t i = 0; i < nodes; ++i) {
    const auto q6 = static_cast<std::uint16_t>((i * 16) % 23040);
    const auto n =
        encode_standard_node(q6 < 16, 47, q6, static_cast<std::uint16_t>(4000 + i % 999));
    s.insert(s.end(), n.begin(), n.end());
  }
  return s;
}

std::vector<std::uint8_t> express_stream(std::size_t capsules) {
  std::vector<std::uint8_t> s;
  for (std::size_t i = 0; i < capsules; ++i) {
    std::array<std::uint8_t, kCapsuleSize> c{};
    const auto start = static_cast<std::uint16_t>((i * 16 * 64 / 10) % 23040);
    c[2] = static_cast<std::uint8_t>(start & 0xFF);
    c[3] = static_cast<std::uint8_t>(start >> 8);
    for (std::size_t k = 4; k < kCapsuleSize; ++k) c[k] = static_cast<std::uint8_t>(k * 7 + i);
    seal_capsule(c);
    s.insert(s.end(), c.begin(), c.end());
  }
  return s;
}

void run_decoder(benchmark::State& state, AnswerType type, const std::vector<std::uint8_t>& body) {
  const auto desc = encode_descriptor(type);
  std::uint64_t nodes = 0;
  for (auto _ : state) {
    Decoder d;
    d.expect(type);
    std::span<const std::uint8_t> rest(desc);
    while (!rest.empty()) rest = rest.subspan(d.decode(rest).consumed);
    rest = body;
    while (!rest.empty()) {
      const DecodeStep step = d.decode(rest);
      rest = rest.subspan(step.consumed);
      if (step.produced) nodes += d.message().nodes.count;
    }
    benchmark::DoNotOptimize(nodes);
  }
  state.SetBytesProcessed(state.iterations() * static_cast<std::int64_t>(body.size()));
  state.counters["nodes/s"] =
      benchmark::Counter(static_cast<double>(nodes), benchmark::Counter::kIsRate);
}

void BM_DecodeStandard(benchmark::State& state) {
  static const auto body = standard_stream(20000);
  run_decoder(state, AnswerType::kMeasurement, body);
}
BENCHMARK(BM_DecodeStandard);

void BM_DecodeExpress(benchmark::State& state) {
  static const auto body = express_stream(1000);
  run_decoder(state, AnswerType::kCapsule, body);
}
BENCHMARK(BM_DecodeExpress);

// One revolution of 1440 points per iteration (node adds + sort + copy at the seam).
void BM_AssembleRevolution1440(benchmark::State& state) {
  ScanAssemblerParams p;
  p.mount.yaw_deg = 180.0;
  p.max_range_m = 40.0F;
  p.sample_duration_us = 69.4;
  auto a = std::make_unique<ScanAssembler>(p);
  std::array<HqNode, 1440> rev{};
  for (std::size_t i = 0; i < rev.size(); ++i) {
    rev[i].angle_z_q14 = static_cast<std::uint16_t>((i * 65536) / 1440);
    rev[i].dist_mm_q2 = static_cast<std::uint32_t>(4000 + (i * 37) % 20000);
    rev[i].quality = 188;
  }
  std::int64_t t = 0;
  std::uint64_t scans = 0;
  for (auto _ : state) {
    for (const HqNode& n : rev) scans += a->add(n, t += 69'400) ? 1U : 0U;
  }
  benchmark::DoNotOptimize(scans);
  state.counters["scans"] = static_cast<double>(scans);
}
BENCHMARK(BM_AssembleRevolution1440);

}  // namespace
}  // namespace coxswain::drivers::rplidar
