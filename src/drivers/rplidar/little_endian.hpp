// SPDX-License-Identifier: Apache-2.0
#pragma once
// Little-endian stores for the RPLIDAR protocol's requests and answers (every multi-byte field
// of the protocol is little-endian: docs/protocols.md, RPLIDAR).
#include <cstdint>

namespace coxswain::drivers::rplidar {

inline void put_u16(std::uint8_t* p, std::uint16_t v) {
  p[0] = static_cast<std::uint8_t>(v & 0xFFU);
  p[1] = static_cast<std::uint8_t>(v >> 8U);
}

inline void put_u32(std::uint8_t* p, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<std::uint8_t>((v >> (8 * i)) & 0xFFU);
}

}  // namespace coxswain::drivers::rplidar
