// SPDX-License-Identifier: Apache-2.0
// myAHRS+ decoder throughput (MB/s) on ASCII `$RPYIMU` lines and on binary e+i frames, both
// generated here (1000 messages each, varying values so number parsing does real work).
#include <benchmark/benchmark.h>

#include <cstdint>
#include <cstdio>
#include <span>
#include <string>
#include <vector>

#include "coxswain/drivers/myahrs/codec.hpp"

namespace coxswain::drivers::myahrs {
namespace {

constexpr int kMessages = 1000;

std::vector<std::uint8_t> ascii_stream() {
  std::vector<std::uint8_t> out;
  char body[256];
  for (int k = 0; k < kMessages; ++k) {
    const double t = static_cast<double>(k);
    const int n = std::snprintf(
        body, sizeof body,
        "$RPYIMU,%02d,%.2f,%.2f,%.2f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.1f", k % 100,
        -1.55 + t * 0.001, -1.25, -179.0 + t * 0.35, -0.0142, -0.0010, -0.9224, -0.9756 + t * 1e-3,
        -0.3659, -0.8537, -8.4, -46.8, 5.4, 38.3);
    std::uint8_t cs = 0;
    for (int i = 0; i < n; ++i)
      cs = static_cast<std::uint8_t>(cs ^ static_cast<std::uint8_t>(body[i]));
    char tail[8];
    std::snprintf(tail, sizeof tail, "*%02X\r\n", cs);
    out.insert(out.end(), body, body + n);
    out.insert(out.end(), tail, tail + 5);
  }
  return out;
}

void put_i16(std::vector<std::uint8_t>& b, int v) {
  const auto u = static_cast<std::uint16_t>(static_cast<std::int16_t>(v));
  b.push_back(static_cast<std::uint8_t>(u & 0xFF));
  b.push_back(static_cast<std::uint8_t>(u >> 8));
}

std::vector<std::uint8_t> binary_stream() {
  std::vector<std::uint8_t> out;
  for (int k = 0; k < kMessages; ++k) {
    std::vector<std::uint8_t> body{0x80, 'd', 0, 0x42, 's', 0, static_cast<std::uint8_t>(k)};
    body.insert(body.end(), {0x63, 'e', 0, 3, 0});
    for (int v : {k * 7, -k * 3, k * 31 - 16000}) put_i16(body, v);
    body.insert(body.end(), {0x23, 'i', 0, 10, 0});
    for (int j = 0; j < 10; ++j) put_i16(body, (k * (j + 1) * 37) % 30000 - 15000);
    std::uint8_t cs = 0;
    for (const std::uint8_t b : body) cs = static_cast<std::uint8_t>(cs ^ b);
    body.push_back(cs);
    out.push_back(kDle);
    out.push_back(kStx);
    for (const std::uint8_t b : body) {
      out.push_back(b);
      if (b == kDle) out.push_back(kDle);
    }
    out.push_back(kDle);
    out.push_back(kEtx);
  }
  return out;
}

void decode_stream(benchmark::State& state, const std::vector<std::uint8_t>& stream) {
  Decoder d;
  std::size_t produced = 0;
  for (auto _ : state) {
    std::span<const std::uint8_t> rest(stream);
    while (!rest.empty()) {
      const DecodeStep step = d.decode(rest);
      rest = rest.subspan(step.consumed);
      if (step.produced) {
        ++produced;
        benchmark::DoNotOptimize(d.sample().yaw_magnetic_deg);
      }
    }
  }
  if (produced != static_cast<std::size_t>(state.iterations()) * kMessages) {
    state.SkipWithError("decoder lost messages");
  }
  state.SetBytesProcessed(state.iterations() * static_cast<std::int64_t>(stream.size()));
  state.SetItemsProcessed(state.iterations() * kMessages);
}

void BM_DecodeAsciiRpyImu(benchmark::State& state) {
  const auto stream = ascii_stream();
  decode_stream(state, stream);
}
BENCHMARK(BM_DecodeAsciiRpyImu);

void BM_DecodeBinaryEulerImu(benchmark::State& state) {
  const auto stream = binary_stream();
  decode_stream(state, stream);
}
BENCHMARK(BM_DecodeBinaryEulerImu);

}  // namespace
}  // namespace coxswain::drivers::myahrs
