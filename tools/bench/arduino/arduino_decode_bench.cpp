// SPDX-License-Identifier: Apache-2.0
// Decode throughput of the Arduino link: the portable FrameDecoder on the firmware's input
// (SetOutputs stream, fed whole and byte by byte as the sketch does) and the daemon's
// ArduinoCodec on a Telemetry stream with some line noise.
#include <benchmark/benchmark.h>

#include <cstdint>
#include <span>
#include <vector>

#include "coxswain/drivers/arduino/codec.hpp"
#include "coxswain/drivers/arduino/wire.hpp"

namespace coxswain::drivers::arduino {
namespace {

std::vector<std::uint8_t> set_outputs_stream(std::size_t frames) {
  std::vector<std::uint8_t> s;
  std::uint8_t buf[kMaxFrame];
  for (std::size_t i = 0; i < frames; ++i) {
    const auto v = static_cast<std::uint16_t>(1100 + i % 800);
    const SetOutputs so{{v, v}, 2, kFlagArm};
    const std::size_t n = encode(so, static_cast<std::uint16_t>(i), buf, sizeof(buf));
    s.insert(s.end(), buf, buf + n);
  }
  return s;
}

std::vector<std::uint8_t> telemetry_stream(std::size_t frames, bool noise) {
  std::vector<std::uint8_t> s;
  std::uint8_t buf[kMaxFrame];
  Telemetry t{};
  for (std::size_t i = 0; i < frames; ++i) {
    t.uptime_ms = static_cast<std::uint32_t>(i * 50);
    const std::size_t n = encode(t, static_cast<std::uint16_t>(i), buf, sizeof(buf));
    s.insert(s.end(), buf, buf + n);
    if (noise && i % 10 == 0) {
      s.insert(s.end(), {0x00, 0xA5, 0x13, 0x37});
      if (s.size() > 30) s[s.size() - 30] ^= 0x40;  // corrupt the frame just written
    }
  }
  return s;
}

void BM_FrameDecoderSetOutputs(benchmark::State& state) {
  const auto s = set_outputs_stream(4096);
  std::uint64_t frames = 0;
  for (auto _ : state) {
    FrameDecoder d;
    std::size_t pos = 0;
    while (pos < s.size()) {
      bool produced = false;
      pos += d.decode(s.data() + pos, s.size() - pos, &produced);
      frames += produced ? 1U : 0U;
    }
    benchmark::DoNotOptimize(frames);
  }
  state.SetBytesProcessed(state.iterations() * static_cast<std::int64_t>(s.size()));
}
BENCHMARK(BM_FrameDecoderSetOutputs);

void BM_FrameDecoderBytewise(benchmark::State& state) {
  const auto s = set_outputs_stream(4096);
  std::uint64_t frames = 0;
  for (auto _ : state) {
    FrameDecoder d;
    for (const std::uint8_t b : s) frames += d.push(b) ? 1U : 0U;
    benchmark::DoNotOptimize(frames);
  }
  state.SetBytesProcessed(state.iterations() * static_cast<std::int64_t>(s.size()));
}
BENCHMARK(BM_FrameDecoderBytewise);

void BM_CodecTelemetry(benchmark::State& state) {
  const auto s = telemetry_stream(2048, state.range(0) != 0);
  for (auto _ : state) {
    ArduinoCodec codec;
    std::span<const std::uint8_t> rest(s);
    while (!rest.empty()) {
      const DecodeStep step = codec.decode(rest);
      rest = rest.subspan(step.consumed);
      if (step.produced) benchmark::DoNotOptimize(codec.message().telemetry.uptime_ms);
    }
  }
  state.SetBytesProcessed(state.iterations() * static_cast<std::int64_t>(s.size()));
}
BENCHMARK(BM_CodecTelemetry)->Arg(0)->Arg(1)->ArgName("noise");

}  // namespace
}  // namespace coxswain::drivers::arduino
