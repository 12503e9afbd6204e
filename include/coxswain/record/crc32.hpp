// SPDX-License-Identifier: Apache-2.0
#pragma once
// CRC-32 as MCAP uses it (ISO-HDLC / zlib: polynomial 0x04C11DB7 reflected, init and final xor
// 0xFFFFFFFF). Incremental: crc32_update(crc32_update(0, a), b) == crc32(a ++ b).
#include <cstdint>
#include <span>

namespace coxswain::record {

/// Continues a CRC-32 over `bytes`; start with `crc` = 0. Pure, thread-safe.
[[nodiscard]] std::uint32_t crc32_update(std::uint32_t crc, std::span<const std::uint8_t> bytes);

[[nodiscard]] inline std::uint32_t crc32(std::span<const std::uint8_t> bytes) {
  return crc32_update(0, bytes);
}

}  // namespace coxswain::record
