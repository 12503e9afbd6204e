// SPDX-License-Identifier: Apache-2.0
#include "coxswain/record/crc32.hpp"

#include <array>

namespace coxswain::record {
namespace {

// Slicing-by-4 tables: table[0] is the classic byte table, table[k] advances k more zero bytes,
// so four input bytes are folded per step (the recorder checksums every byte it writes).
constexpr std::array<std::array<std::uint32_t, 256>, 4> make_tables() {
  std::array<std::array<std::uint32_t, 256>, 4> t{};
  for (std::uint32_t i = 0; i < 256; ++i) {
    std::uint32_t c = i;
    for (int k = 0; k < 8; ++k) c = (c & 1U) != 0 ? 0xEDB88320U ^ (c >> 1) : c >> 1;
    t[0][i] = c;
  }
  for (std::uint32_t i = 0; i < 256; ++i) {
    for (std::size_t k = 1; k < 4; ++k) t[k][i] = (t[k - 1][i] >> 8) ^ t[0][t[k - 1][i] & 0xFFU];
  }
  return t;
}

constexpr auto kTables = make_tables();

}  // namespace

std::uint32_t crc32_update(std::uint32_t crc, std::span<const std::uint8_t> bytes) {
  std::uint32_t c = ~crc;
  std::size_t i = 0;
  const std::size_t n = bytes.size();
  for (; i + 4 <= n; i += 4) {
    c ^= static_cast<std::uint32_t>(bytes[i]) | (static_cast<std::uint32_t>(bytes[i + 1]) << 8) |
         (static_cast<std::uint32_t>(bytes[i + 2]) << 16) |
         (static_cast<std::uint32_t>(bytes[i + 3]) << 24);
    c = kTables[3][c & 0xFFU] ^ kTables[2][(c >> 8) & 0xFFU] ^ kTables[1][(c >> 16) & 0xFFU] ^
        kTables[0][c >> 24];
  }
  for (; i < n; ++i) c = kTables[0][(c ^ bytes[i]) & 0xFFU] ^ (c >> 8);
  return ~c;
}

}  // namespace coxswain::record
