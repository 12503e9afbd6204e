// SPDX-License-Identifier: Apache-2.0
// libFuzzer target for the myAHRS+ decoder: arbitrary bytes, fed whole and then split at a
// data-derived point, must never crash, must always make progress, must produce the same
// messages both ways, and must keep the counters consistent.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <span>

#include "coxswain/drivers/myahrs/codec.hpp"

namespace {

using coxswain::drivers::myahrs::Decoder;
using coxswain::drivers::myahrs::Output;

void check(bool ok) {
  if (!ok) std::abort();
}

// A cheap order-sensitive digest of what was produced.
struct Digest {
  std::uint64_t value = 1469598103934665603ULL;
  std::size_t count = 0;
  void mix(std::uint64_t v) { value = (value ^ v) * 1099511628211ULL; }
};

void run(Decoder& d, std::span<const std::uint8_t> bytes, Digest& digest) {
  while (!bytes.empty()) {
    const auto step = d.decode(bytes);
    check(step.consumed >= 1 && step.consumed <= bytes.size());
    bytes = bytes.subspan(step.consumed);
    if (!step.produced) continue;
    ++digest.count;
    if (d.last_output() == Output::kSample) {
      const auto& s = d.sample();
      check(std::isfinite(s.roll_deg) && std::isfinite(s.yaw_magnetic_deg));
      check(s.heading_deg > -180.0 - 1e-9 && s.heading_deg <= 180.0 + 1e-9);
      digest.mix(s.sequence);
      digest.mix(static_cast<std::uint64_t>(std::llround(s.yaw_magnetic_deg * 1000.0)));
      digest.mix(static_cast<std::uint64_t>(std::llround(s.accel_g[2] * 1000.0)));
    } else {
      check(d.last_output() == Output::kResponse);
      const auto& r = d.response();
      check(!r.command.empty());
      digest.mix(r.command.size());
      digest.mix(r.attributes.size());
      for (const auto& a : r.attributes) digest.mix(a.name.size() * 131 + a.value.size());
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::uint8_t> bytes(data, size);
  Decoder whole;
  Digest a;
  run(whole, bytes, a);
  const auto& st = whole.stats();
  check(st.codec.bytes_in == size);
  check(st.codec.messages_out == a.count);
  check(st.codec.bytes_skipped <= size);

  const std::size_t cut = size == 0 ? 0 : static_cast<std::size_t>(data[0]) % (size + 1);
  Decoder split;
  Digest b;
  run(split, bytes.first(cut), b);
  run(split, bytes.subspan(cut), b);
  check(a.value == b.value && a.count == b.count);
  check(split.stats().codec.framing_errors == st.codec.framing_errors);
  check(split.stats().codec.checksum_errors == st.codec.checksum_errors);
  return 0;
}
