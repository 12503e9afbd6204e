// SPDX-License-Identifier: Apache-2.0
// Decode throughput of the u-blox stream decoder and the RTCM 3 framer.
//  * BM_DecodeMixedStream: a generated F9P-like stream, 10 Hz epochs of NAV-PVT + NAV-HPPOSLLH +
//    NAV-EOE + NMEA GGA/RMC, with a 1 Hz burst of RTCM 3 MSM7 frames, fed in 512-byte reads.
//  * BM_DecodeGpsdCapture: gpsd's ublox-zed-f9t-rtcm3.log (UBX + RTCM 3), if present.
//  * BM_Rtcm3Framer: the framer on a pure correction stream.
#include <benchmark/benchmark.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "coxswain/drivers/ublox/codec.hpp"
#include "coxswain/drivers/ublox/config.hpp"

namespace {

using coxswain::drivers::DecodeStep;
using namespace coxswain::drivers::ublox;

void append(std::vector<std::uint8_t>& dst, std::span<const std::uint8_t> src) {
  dst.insert(dst.end(), src.begin(), src.end());
}

void append_nmea(std::vector<std::uint8_t>& dst, const std::string& body) {
  unsigned x = 0;
  for (const char c : body) x ^= static_cast<unsigned char>(c);
  std::array<char, 8> tail{};
  std::snprintf(tail.data(), tail.size(), "*%02X\r\n", x);
  const std::string s = "$" + body + tail.data();
  dst.insert(dst.end(), s.begin(), s.end());
}

std::vector<std::uint8_t> rtcm3(std::uint16_t type, std::size_t len, std::uint8_t seed) {
  std::vector<std::uint8_t> f{kRtcm3Preamble, static_cast<std::uint8_t>(len >> 8),
                              static_cast<std::uint8_t>(len & 0xFF)};
  for (std::size_t i = 0; i < len; ++i) f.push_back(static_cast<std::uint8_t>(seed + i * 37));
  f[3] = static_cast<std::uint8_t>(type >> 4);
  f[4] = static_cast<std::uint8_t>((type & 0x0F) << 4);
  const std::uint32_t crc = crc24q(f);
  f.push_back(static_cast<std::uint8_t>(crc >> 16));
  f.push_back(static_cast<std::uint8_t>(crc >> 8));
  f.push_back(static_cast<std::uint8_t>(crc));
  return f;
}

std::vector<std::uint8_t> mixed_stream(int seconds) {
  std::vector<std::uint8_t> s;
  for (int epoch = 0; epoch < seconds * 10; ++epoch) {
    const auto itow = static_cast<std::uint32_t>(100'000'000 + epoch * 100);
    std::array<std::uint8_t, 92> pvt{};
    for (int i = 0; i < 4; ++i)
      pvt[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(itow >> (8 * i));
    pvt[4] = 0xE8;
    pvt[5] = 0x07;
    pvt[6] = 5;
    pvt[7] = 17;
    pvt[8] = 3;
    pvt[9] = 4;
    pvt[10] = static_cast<std::uint8_t>(epoch / 10 % 60);
    pvt[11] = 0x37;
    pvt[20] = 3;
    pvt[21] = 0x83;
    pvt[23] = 24;
    pvt[24] = static_cast<std::uint8_t>(epoch);
    pvt[27] = 0x4B;
    pvt[31] = 0x14;
    append(s, make_ubx_frame(kNavPvt, pvt).bytes());
    std::array<std::uint8_t, 36> hp{};
    for (int i = 0; i < 4; ++i)
      hp[static_cast<std::size_t>(4 + i)] = static_cast<std::uint8_t>(itow >> (8 * i));
    append(s, make_ubx_frame(kNavHpPosLlh, hp).bytes());
    std::array<std::uint8_t, 4> eoe{};
    append(s, make_ubx_frame(UbxId{0x01, 0x61}, eoe).bytes());
    char tod[16];
    std::snprintf(tod, sizeof tod, "0304%02d.%02d", epoch / 10 % 60, epoch % 10 * 10);
    append_nmea(
        s, std::string("GNRMC,") + tod + ",A,3507.12345,N,12648.00000,E,3.1,271.5,170524,,,R,V");
    append_nmea(s, std::string("GNGGA,") + tod +
                       ",3507.12345,N,12648.00000,E,4,24,0.51,12.3,M,20.1,M,1.0,0000");
    if (epoch % 10 == 0) {
      append(s, rtcm3(1005, 19, 1));
      append(s, rtcm3(1077, 420, 2));
      append(s, rtcm3(1087, 300, 3));
      append(s, rtcm3(1097, 350, 4));
      append(s, rtcm3(1127, 380, 5));
    }
  }
  return s;
}

std::int64_t decode_stream(Decoder& d, const std::vector<std::uint8_t>& bytes, std::size_t read) {
  std::int64_t produced = 0;
  for (std::size_t off = 0; off < bytes.size(); off += read) {
    std::span<const std::uint8_t> rest =
        std::span(bytes).subspan(off, std::min(read, bytes.size() - off));
    while (!rest.empty()) {
      const DecodeStep step = d.decode(rest);
      rest = rest.subspan(step.consumed);
      produced += step.produced ? 1 : 0;
    }
  }
  return produced;
}

void BM_DecodeMixedStream(benchmark::State& state) {
  const auto bytes = mixed_stream(60);
  const auto read = static_cast<std::size_t>(state.range(0));
  std::int64_t messages = 0;
  for (auto _ : state) {
    Decoder d;
    messages += decode_stream(d, bytes, read);
    benchmark::DoNotOptimize(d.stats());
  }
  state.SetBytesProcessed(state.iterations() * static_cast<std::int64_t>(bytes.size()));
  state.SetItemsProcessed(messages);
}
BENCHMARK(BM_DecodeMixedStream)->Arg(1)->Arg(64)->Arg(512)->Arg(4096);

void BM_DecodeGpsdCapture(benchmark::State& state) {
  const char* env = std::getenv("COXSWAIN_SHARED_TESTDATA");
  const std::filesystem::path path =
      std::filesystem::path(env != nullptr ? env : COXSWAIN_BENCH_TESTDATA) / "gpsd" /
      "ublox-zed-f9t-rtcm3.log";
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    state.SkipWithError("shared test data absent: gpsd/ublox-zed-f9t-rtcm3.log");
    return;
  }
  const std::vector<std::uint8_t> bytes{std::istreambuf_iterator<char>(in),
                                        std::istreambuf_iterator<char>()};
  std::int64_t messages = 0;
  for (auto _ : state) {
    Decoder d;
    messages += decode_stream(d, bytes, 512);
    benchmark::DoNotOptimize(d.stats());
  }
  state.SetBytesProcessed(state.iterations() * static_cast<std::int64_t>(bytes.size()));
  state.SetItemsProcessed(messages);
}
BENCHMARK(BM_DecodeGpsdCapture);

void BM_Rtcm3Framer(benchmark::State& state) {
  std::vector<std::uint8_t> bytes;
  for (int i = 0; i < 200; ++i) {
    append(bytes, rtcm3(1077, 420, static_cast<std::uint8_t>(i)));
    append(bytes, rtcm3(1230, 8, static_cast<std::uint8_t>(i)));
  }
  for (auto _ : state) {
    Rtcm3Framer f;
    std::span<const std::uint8_t> rest = bytes;
    while (!rest.empty()) rest = rest.subspan(f.decode(rest).consumed);
    benchmark::DoNotOptimize(f.stats());
  }
  state.SetBytesProcessed(state.iterations() * static_cast<std::int64_t>(bytes.size()));
}
BENCHMARK(BM_Rtcm3Framer);

}  // namespace
