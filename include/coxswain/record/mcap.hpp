// SPDX-License-Identifier: Apache-2.0
#pragma once
// MCAP container constants shared by the writer and the reader (https://mcap.dev/spec, major
// version 0). Every record is <opcode u8><content length u64><content>; integers little-endian;
// strings and byte arrays carry a u32 length prefix, maps and arrays a u32 byte-length prefix.
#include <array>
#include <cstdint>

namespace coxswain::record::mcap {

inline constexpr std::array<std::uint8_t, 8> kMagic{0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};

enum class Op : std::uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kMessageIndex = 0x07,
  kChunkIndex = 0x08,
  kAttachment = 0x09,
  kAttachmentIndex = 0x0A,
  kStatistics = 0x0B,
  kMetadata = 0x0C,
  kMetadataIndex = 0x0D,
  kSummaryOffset = 0x0E,
  kDataEnd = 0x0F,
};

/// Opcode + u64 length prefix of every record.
inline constexpr std::size_t kRecordPrefixBytes = 9;

}  // namespace coxswain::record::mcap
