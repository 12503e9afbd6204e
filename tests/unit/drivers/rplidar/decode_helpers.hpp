// SPDX-License-Identifier: Apache-2.0
#pragma once
// Test helpers: run a Decoder over a byte stream and collect what it produced.
#include <cstdint>
#include <span>
#include <vector>

#include "coxswain/drivers/rplidar/codec.hpp"

namespace coxswain::drivers::rplidar::test {

struct Collected {
  std::vector<Message> messages;  // single answers and node batches, in order
  std::vector<HqNode> nodes;      // every node of every batch, in order
};

inline void decode_into(Decoder& d, std::span<const std::uint8_t> bytes, Collected& out) {
  while (!bytes.empty()) {
    const DecodeStep step = d.decode(bytes);
    if (step.consumed == 0) break;  // convention: never happens for non-empty input
    bytes = bytes.subspan(step.consumed);
    if (!step.produced) continue;
    out.messages.push_back(d.message());
    if (d.message().kind == MessageKind::kNodes) {
      for (const HqNode& n : d.message().nodes.span()) out.nodes.push_back(n);
    }
  }
}

inline Collected decode_all(Decoder& d, std::span<const std::uint8_t> bytes) {
  Collected c;
  decode_into(d, bytes, c);
  return c;
}

inline void append(std::vector<std::uint8_t>& v, std::span<const std::uint8_t> bytes) {
  v.insert(v.end(), bytes.begin(), bytes.end());
}

}  // namespace coxswain::drivers::rplidar::test
