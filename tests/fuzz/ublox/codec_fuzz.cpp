// SPDX-License-Identifier: Apache-2.0
// libFuzzer target for the u-blox stream decoder and the RTCM 3 framer. The first input byte
// chooses the chunk size, so frames arrive split at varying boundaries. Checks the codec
// contract: progress on every call, byte accounting, and frame views inside the input's size.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <span>

#include "coxswain/drivers/ublox/codec.hpp"

namespace {

using coxswain::drivers::DecodeStep;
using coxswain::drivers::ublox::Decoder;
using coxswain::drivers::ublox::MessageKind;
using coxswain::drivers::ublox::Rtcm3Framer;

void check(bool ok) {
  if (!ok) std::abort();
}

template <typename Codec, typename OnFrame>
void run(Codec& codec, std::span<const std::uint8_t> bytes, std::size_t chunk, OnFrame on_frame) {
  for (std::size_t off = 0; off < bytes.size(); off += chunk) {
    auto rest = bytes.subspan(off, std::min(chunk, bytes.size() - off));
    while (!rest.empty()) {
      const DecodeStep step = codec.decode(rest);
      check(step.consumed >= 1 && step.consumed <= rest.size());
      rest = rest.subspan(step.consumed);
      if (step.produced) on_frame();
    }
  }
  while (codec.decode({}).produced) on_frame();
  check(codec.stats().bytes_in == bytes.size());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::size_t chunk = static_cast<std::size_t>(data[0] % 64) + 1;
  const std::span<const std::uint8_t> bytes(data + 1, size - 1);

  Decoder decoder;
  std::uint64_t produced = 0;
  run(decoder, bytes, chunk, [&] {
    ++produced;
    const auto& m = decoder.message();
    check(m.kind != MessageKind::kNone);
    if (m.kind == MessageKind::kRtcm3) {
      check(m.rtcm3.bytes.size() >= 6 && m.rtcm3.bytes.size() <= 1029);
      check(m.rtcm3.bytes[0] == 0xD3);
    }
    if (m.kind == MessageKind::kFix) {
      // NMEA coordinates are range-checked by the decoder; NAV-PVT passes raw values through.
      check(m.fix.source == coxswain::msg::GnssSource::kUbxNavPvt ||
            (m.fix.lat_deg >= -90.0 && m.fix.lat_deg <= 90.0));
      check(m.fix.course_deg > -180.0 - 1e-9 && m.fix.course_deg <= 180.0 + 1e-9);
    }
  });
  check(decoder.stats().messages_out == produced);

  Rtcm3Framer framer;
  std::uint64_t frames = 0;
  run(framer, bytes, chunk, [&] {
    ++frames;
    check(framer.frame().bytes.size() >= 6 && framer.frame().bytes[0] == 0xD3);
  });
  // The framer sees exactly the RTCM frames the full decoder saw only if nothing else
  // overlapped; at least it never accepts more CRC-valid frames than bytes allow.
  check(frames * 6 <= bytes.size());
  return 0;
}
