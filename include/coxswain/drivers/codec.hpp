// SPDX-License-Identifier: Apache-2.0
#pragma once
// Shared shape of every device codec (docs/architecture.md): a codec is pure. It takes bytes and
// returns at most one message per call plus how many bytes it consumed; it never does I/O, never
// reads a clock, never logs and never allocates after construction. The caller (an adapter, a
// test, a fuzzer or `coxswain decode`) loops:
//
//   std::span<const std::uint8_t> rest = bytes;
//   while (!rest.empty()) {
//     const DecodeStep step = decoder.decode(rest);
//     rest = rest.subspan(step.consumed);
//     if (step.produced) use(decoder.message());
//   }
//
// A decoder keeps any partial frame internally, so bytes may arrive split anywhere. `consumed`
// is always >= 1 when the input is non-empty, so the loop always terminates.
#include <cstddef>
#include <cstdint>

namespace coxswain::drivers {

struct DecodeStep {
  std::size_t consumed = 0;
  bool produced = false;
};

/// Error and traffic counters every codec keeps; adapters copy them into DeviceHealth.
struct CodecStats {
  std::uint64_t bytes_in = 0;
  std::uint64_t frames_ok = 0;        // checksummed frames accepted (any kind)
  std::uint64_t messages_out = 0;     // messages produced for the caller
  std::uint64_t checksum_errors = 0;  // frames whose checksum/CRC failed
  std::uint64_t framing_errors = 0;   // bad sync, impossible length, malformed fields
  std::uint64_t bytes_skipped = 0;    // bytes dropped while hunting for a frame start
  std::uint64_t unsupported = 0;      // valid frames of kinds this codec ignores
};

}  // namespace coxswain::drivers
