// SPDX-License-Identifier: Apache-2.0
#pragma once
// Writes an indexed, chunked, zstd-compressed MCAP file (https://mcap.dev/spec), built for a
// flight recorder that may die at any moment:
//  - Schema, Channel, Metadata and Attachment records go to the data section as they are added;
//    Messages collect in an open chunk that is compressed, written with its MessageIndex records
//    and flushed to disk (write(2) then fdatasync(2) unless disabled) by close_chunk(). A reader
//    of a file cut anywhere recovers every chunk closed before the cut (McapReader does).
//  - close() adds DataEnd (CRC-32 of the data section), the summary (schemas, channels,
//    Statistics, chunk/metadata/attachment indexes, SummaryOffsets) and the Footer (summary CRC).
//  - Any write error (ENOSPC, EIO, ...) makes the writer fail: it stops writing, keeps the error
//    text and returns false from then on; it never throws into the caller.
// Thread-safety: none; one owner (the recorder's writer thread).
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace coxswain::record {

struct McapWriterOptions {
  std::string profile;  // MCAP Header profile ("" = none)
  std::string library = "coxswain";
  /// An open chunk is closed when its uncompressed records reach this size.
  std::size_t chunk_size_bytes = 4U << 20U;
  bool compress = true;  // zstd chunks; false writes uncompressed chunks
  int zstd_level = 3;
  /// fdatasync(2) after every closed chunk (and at close), so a power loss keeps closed chunks.
  bool sync = true;
  /// Bytes buffered in memory before a write(2) outside chunk closes.
  std::size_t buffer_bytes = 1U << 20U;
};

struct McapWriterStats {
  std::uint64_t messages = 0;
  std::uint64_t chunks = 0;
  std::uint64_t bytes_written = 0;  // handed to the kernel
  std::uint64_t uncompressed_chunk_bytes = 0;
  std::uint64_t syncs = 0;
  std::map<std::uint16_t, std::uint64_t> channel_message_counts;
};

using McapMetadataMap = std::map<std::string, std::string>;

class McapWriter {
 public:
  explicit McapWriter(McapWriterOptions options = {});
  ~McapWriter();
  McapWriter(const McapWriter&) = delete;
  McapWriter& operator=(const McapWriter&) = delete;

  /// Creates (truncates) `path` and writes the magic and Header. False (and failed()) on error.
  [[nodiscard]] bool open(const std::filesystem::path& path);
  /// Same over an already open file descriptor (e.g. /dev/full in tests); the writer closes it.
  [[nodiscard]] bool open_fd(int fd, std::string name);

  /// Registers a schema; returns its id (>= 1), or 0 when the writer has failed.
  std::uint16_t add_schema(std::string_view name, std::string_view encoding,
                           std::span<const std::uint8_t> data);
  std::uint16_t add_schema(std::string_view name, std::string_view encoding, std::string_view data);
  /// Registers a channel on `schema_id` (0 = schemaless); returns its id, or 0xFFFF on failure.
  std::uint16_t add_channel(std::uint16_t schema_id, std::string_view topic,
                            std::string_view message_encoding,
                            const McapMetadataMap& metadata = {});

  /// Appends a message to the open chunk (sequence numbers count per channel from 1); closes the
  /// chunk when it is full. False when the writer has failed or the channel is unknown.
  bool write_message(std::uint16_t channel_id, std::uint64_t log_time_ns,
                     std::uint64_t publish_time_ns, std::span<const std::uint8_t> data);
  bool write_metadata(std::string_view name, const McapMetadataMap& values);
  bool write_attachment(std::string_view name, std::string_view media_type,
                        std::uint64_t log_time_ns, std::uint64_t create_time_ns,
                        std::span<const std::uint8_t> data);

  /// Writes the open chunk (if any message is in it), flushes and syncs. Call it periodically:
  /// it bounds what a crash can lose.
  bool close_chunk();
  /// Finishes the file (DataEnd, summary, footer) and closes the descriptor. Idempotent.
  bool close();

  [[nodiscard]] bool is_open() const { return fd_ >= 0; }
  [[nodiscard]] bool failed() const { return failed_; }
  [[nodiscard]] const std::string& error() const { return error_; }
  [[nodiscard]] const McapWriterStats& stats() const { return stats_; }
  /// Uncompressed bytes in the open chunk.
  [[nodiscard]] std::size_t open_chunk_bytes() const { return chunk_.size(); }
  [[nodiscard]] std::size_t open_chunk_messages() const { return chunk_messages_; }

 private:
  struct Schema {
    std::uint16_t id;
    std::string name;
    std::string encoding;
    std::vector<std::uint8_t> data;
  };
  struct Channel {
    std::uint16_t id;
    std::uint16_t schema_id;
    std::string topic;
    std::string message_encoding;
    McapMetadataMap metadata;
    std::uint32_t sequence = 0;
  };
  struct ChunkIndex {
    std::uint64_t start_ns, end_ns, chunk_offset, chunk_length, index_length, compressed_size,
        uncompressed_size;
    std::vector<std::pair<std::uint16_t, std::uint64_t>> index_offsets;
  };
  struct MetadataIndex {
    std::uint64_t offset, length;
    std::string name;
  };
  struct AttachmentIndex {
    std::uint64_t offset, length, log_time, create_time, data_size;
    std::string name, media_type;
  };

  bool start_file();
  void emit_record(std::uint8_t op, std::span<const std::uint8_t> content);
  /// Appends bytes to the output stream (buffer, data-section CRC, offsets).
  void emit(std::span<const std::uint8_t> bytes);
  bool flush_buffer();
  bool sync_file();
  void fail(std::string what, int err);
  static void encode_schema(std::vector<std::uint8_t>& out, const Schema& s);
  static void encode_channel(std::vector<std::uint8_t>& out, const Channel& c);
  std::uint64_t offset() const { return file_offset_; }

  McapWriterOptions options_;
  int fd_ = -1;
  std::string name_;
  bool failed_ = false;
  bool closed_ = false;
  std::string error_;
  bool in_data_section_ = true;
  std::uint32_t data_crc_ = 0;
  std::uint64_t file_offset_ = 0;  // bytes emitted so far (written or buffered)
  std::vector<std::uint8_t> out_;  // buffered output not yet written
  std::vector<std::uint8_t> scratch_;

  std::vector<Schema> schemas_;
  std::vector<Channel> channels_;

  // The open chunk: uncompressed records and the per-channel message index.
  std::vector<std::uint8_t> chunk_;
  std::size_t chunk_messages_ = 0;
  std::uint64_t chunk_start_ns_ = 0;
  std::uint64_t chunk_end_ns_ = 0;
  std::map<std::uint16_t, std::vector<std::pair<std::uint64_t, std::uint64_t>>> chunk_index_;
  std::vector<std::uint8_t> compressed_;
  void* zstd_ = nullptr;  // ZSTD_CCtx*, kept out of the header

  std::uint64_t message_start_ns_ = 0;
  std::uint64_t message_end_ns_ = 0;
  std::vector<ChunkIndex> chunk_indexes_;
  std::vector<MetadataIndex> metadata_indexes_;
  std::vector<AttachmentIndex> attachment_indexes_;
  McapWriterStats stats_;
};

}  // namespace coxswain::record
