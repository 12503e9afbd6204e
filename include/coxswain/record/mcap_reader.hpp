// SPDX-License-Identifier: Apache-2.0
#pragma once
// Reads MCAP files written by McapWriter (and other well-formed MCAP files with zstd or
// uncompressed chunks) front to back, checking every CRC on the way, including files cut short by
// a crash: every record complete before the cut is used, a partial last record is reported as
// truncation, not as an error. Loads the whole file into memory (recordings of one run).
// Thread-safety: none; one owner.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace coxswain::record {

struct McapSchemaInfo {
  std::uint16_t id = 0;
  std::string name;
  std::string encoding;
  std::vector<std::uint8_t> data;
};

struct McapChannelInfo {
  std::uint16_t id = 0;
  std::uint16_t schema_id = 0;
  std::string topic;
  std::string message_encoding;
  std::map<std::string, std::string> metadata;
};

/// One message; `data` points into the reader's buffers and is valid during the callback only.
struct McapMessageView {
  std::uint16_t channel_id = 0;
  std::uint32_t sequence = 0;
  std::uint64_t log_time_ns = 0;
  std::uint64_t publish_time_ns = 0;
  std::span<const std::uint8_t> data;
};

struct McapStatisticsInfo {
  std::uint64_t message_count = 0;
  std::uint16_t schema_count = 0;
  std::uint32_t channel_count = 0;
  std::uint32_t attachment_count = 0;
  std::uint32_t metadata_count = 0;
  std::uint32_t chunk_count = 0;
  std::uint64_t message_start_ns = 0;
  std::uint64_t message_end_ns = 0;
  std::map<std::uint16_t, std::uint64_t> channel_message_counts;
};

struct McapAttachmentInfo {
  std::string name;
  std::string media_type;
  std::uint64_t log_time_ns = 0;
  std::vector<std::uint8_t> data;
  bool crc_ok = false;
};

/// What a read found. `complete` = DataEnd, summary, footer and closing magic all present.
struct McapReadReport {
  bool header_ok = false;
  std::string profile;
  std::string library;
  bool truncated = false;  // the file ends inside a record (crash): data before it was used
  bool complete = false;
  bool data_crc_ok = false;     // DataEnd CRC matches (only when present and non-zero)
  bool summary_crc_ok = false;  // Footer CRC matches
  bool index_ok = false;  // every ChunkIndex / MessageIndex / SummaryOffset points where it says
  std::uint64_t chunks = 0;
  std::uint64_t chunk_crc_errors = 0;  // chunks skipped: bad CRC or failed decompression
  std::uint64_t messages = 0;
  std::uint64_t message_indexes = 0;
  std::uint64_t summary_offsets = 0;
  std::uint64_t chunk_index_records = 0;
  std::optional<McapStatisticsInfo> statistics;
  std::map<std::string, std::map<std::string, std::string>> metadata;
  std::vector<McapAttachmentInfo> attachments;
  std::string error;  // first malformed record (not truncation), empty when none
};

class McapReader {
 public:
  using MessageFn = std::function<void(const McapMessageView&)>;

  /// Reads the file into memory; false when it cannot be read.
  [[nodiscard]] bool open(const std::filesystem::path& path);
  /// Uses `bytes` as the file content.
  void load(std::vector<std::uint8_t> bytes);

  /// Walks the whole file, calling `on_message` (may be empty) for each message in file order,
  /// and returns what it found. Schemas and channels are available afterwards.
  McapReadReport read(const MessageFn& on_message);

  [[nodiscard]] const std::map<std::uint16_t, McapSchemaInfo>& schemas() const { return schemas_; }
  [[nodiscard]] const std::map<std::uint16_t, McapChannelInfo>& channels() const {
    return channels_;
  }
  /// Channel id of `topic`, if the file has it.
  [[nodiscard]] std::optional<std::uint16_t> channel_id(const std::string& topic) const;
  [[nodiscard]] std::size_t file_size() const { return bytes_.size(); }

 private:
  bool read_records(std::span<const std::uint8_t> records, bool in_chunk, std::uint64_t base,
                    const MessageFn& on_message, McapReadReport& report);
  void verify_indexes(McapReadReport& report);

  std::vector<std::uint8_t> bytes_;
  std::map<std::uint16_t, McapSchemaInfo> schemas_;
  std::map<std::uint16_t, McapChannelInfo> channels_;
  struct ChunkIndexEntry {
    std::uint64_t chunk_offset, chunk_length, index_length;
    std::map<std::uint16_t, std::uint64_t> index_offsets;
  };
  std::vector<ChunkIndexEntry> chunk_indexes_;
  struct SummaryOffsetEntry {
    std::uint8_t op;
    std::uint64_t start, length;
  };
  std::vector<SummaryOffsetEntry> summary_offsets_;
  std::vector<std::uint8_t> decompressed_;
  std::uint64_t summary_start_ = 0;
};

}  // namespace coxswain::record
