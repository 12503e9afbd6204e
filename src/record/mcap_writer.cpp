// SPDX-License-Identifier: Apache-2.0
#include "coxswain/record/mcap_writer.hpp"

#include <fcntl.h>
#include <unistd.h>
#include <zstd.h>

#include <cerrno>
#include <cstring>

#include "coxswain/record/crc32.hpp"
#include "coxswain/record/mcap.hpp"

namespace coxswain::record {
namespace {

using mcap::Op;

void put_u8(std::vector<std::uint8_t>& o, std::uint8_t v) { o.push_back(v); }
template <class U>
void put_le(std::vector<std::uint8_t>& o, U v) {
  for (std::size_t i = 0; i < sizeof(U); ++i) o.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}
void put_u16(std::vector<std::uint8_t>& o, std::uint16_t v) { put_le(o, v); }
void put_u32(std::vector<std::uint8_t>& o, std::uint32_t v) { put_le(o, v); }
void put_u64(std::vector<std::uint8_t>& o, std::uint64_t v) { put_le(o, v); }
void put_bytes(std::vector<std::uint8_t>& o, std::span<const std::uint8_t> b) {
  o.insert(o.end(), b.begin(), b.end());
}
void put_str(std::vector<std::uint8_t>& o, std::string_view s) {
  put_u32(o, static_cast<std::uint32_t>(s.size()));
  o.insert(o.end(), s.begin(), s.end());
}
/// Map<string, string>: u32 byte length, then key/value strings.
void put_str_map(std::vector<std::uint8_t>& o, const McapMetadataMap& m) {
  std::size_t len = 0;
  for (const auto& [k, v] : m) len += 8 + k.size() + v.size();
  put_u32(o, static_cast<std::uint32_t>(len));
  for (const auto& [k, v] : m) {
    put_str(o, k);
    put_str(o, v);
  }
}
std::span<const std::uint8_t> as_bytes(std::string_view s) {
  return {reinterpret_cast<const std::uint8_t*>(s.data()), s.size()};
}

}  // namespace

McapWriter::McapWriter(McapWriterOptions options) : options_(std::move(options)) {
  out_.reserve(options_.buffer_bytes);
}

McapWriter::~McapWriter() {
  close();
  if (zstd_ != nullptr) ZSTD_freeCCtx(static_cast<ZSTD_CCtx*>(zstd_));
}

void McapWriter::fail(std::string what, int err) {
  if (failed_) return;
  failed_ = true;
  error_ = name_ + ": " + std::move(what);
  if (err != 0) error_ += std::string(": ") + std::strerror(err);
}

bool McapWriter::open(const std::filesystem::path& path) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) {
    name_ = path.string();
    fail("cannot create", errno);
    return false;
  }
  return open_fd(fd, path.string());
}

bool McapWriter::open_fd(int fd, std::string name) {
  if (fd_ >= 0 || closed_) {
    if (fd >= 0) ::close(fd);
    fail("writer already used", 0);
    return false;
  }
  fd_ = fd;
  name_ = std::move(name);
  if (options_.compress && zstd_ == nullptr) zstd_ = ZSTD_createCCtx();
  return start_file();
}

bool McapWriter::start_file() {
  emit(mcap::kMagic);
  scratch_.clear();
  put_str(scratch_, options_.profile);
  put_str(scratch_, options_.library);
  emit_record(static_cast<std::uint8_t>(Op::kHeader), scratch_);
  return flush_buffer();
}

void McapWriter::emit(std::span<const std::uint8_t> bytes) {
  if (in_data_section_) data_crc_ = crc32_update(data_crc_, bytes);
  out_.insert(out_.end(), bytes.begin(), bytes.end());
  file_offset_ += bytes.size();
}

void McapWriter::emit_record(std::uint8_t op, std::span<const std::uint8_t> content) {
  std::uint8_t prefix[mcap::kRecordPrefixBytes];
  prefix[0] = op;
  const std::uint64_t len = content.size();
  for (std::size_t i = 0; i < 8; ++i) prefix[1 + i] = static_cast<std::uint8_t>(len >> (8 * i));
  emit(prefix);
  emit(content);
}

bool McapWriter::flush_buffer() {
  if (failed_) return false;
  std::size_t done = 0;
  while (done < out_.size()) {
    const ssize_t n = ::write(fd_, out_.data() + done, out_.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      fail("write failed", errno);
      return false;
    }
    if (n == 0) {
      fail("write made no progress", ENOSPC);
      return false;
    }
    done += static_cast<std::size_t>(n);
    stats_.bytes_written += static_cast<std::uint64_t>(n);
  }
  out_.clear();
  return true;
}

bool McapWriter::sync_file() {
  if (failed_ || !options_.sync) return !failed_;
  // fdatasync on a pipe or character device (tests) is EINVAL: nothing to sync there.
  if (::fdatasync(fd_) != 0 && errno != EINVAL && errno != EROFS) {
    fail("fdatasync failed", errno);
    return false;
  }
  ++stats_.syncs;
  return true;
}

void McapWriter::encode_schema(std::vector<std::uint8_t>& out, const Schema& s) {
  put_u16(out, s.id);
  put_str(out, s.name);
  put_str(out, s.encoding);
  put_u32(out, static_cast<std::uint32_t>(s.data.size()));
  put_bytes(out, s.data);
}

void McapWriter::encode_channel(std::vector<std::uint8_t>& out, const Channel& c) {
  put_u16(out, c.id);
  put_u16(out, c.schema_id);
  put_str(out, c.topic);
  put_str(out, c.message_encoding);
  put_str_map(out, c.metadata);
}

std::uint16_t McapWriter::add_schema(std::string_view name, std::string_view encoding,
                                     std::string_view data) {
  return add_schema(name, encoding, as_bytes(data));
}

std::uint16_t McapWriter::add_schema(std::string_view name, std::string_view encoding,
                                     std::span<const std::uint8_t> data) {
  if (failed_ || fd_ < 0 || schemas_.size() >= 0xFFFE) return 0;
  Schema s{static_cast<std::uint16_t>(schemas_.size() + 1), std::string(name),
           std::string(encoding), std::vector<std::uint8_t>(data.begin(), data.end())};
  scratch_.clear();
  encode_schema(scratch_, s);
  emit_record(static_cast<std::uint8_t>(Op::kSchema), scratch_);
  schemas_.push_back(std::move(s));
  if (out_.size() >= options_.buffer_bytes && !flush_buffer()) return 0;
  return schemas_.back().id;
}

std::uint16_t McapWriter::add_channel(std::uint16_t schema_id, std::string_view topic,
                                      std::string_view message_encoding,
                                      const McapMetadataMap& metadata) {
  if (failed_ || fd_ < 0 || channels_.size() >= 0xFFFE || schema_id > schemas_.size()) {
    return 0xFFFF;
  }
  Channel c{static_cast<std::uint16_t>(channels_.size() + 1), schema_id, std::string(topic),
            std::string(message_encoding), metadata};
  scratch_.clear();
  encode_channel(scratch_, c);
  emit_record(static_cast<std::uint8_t>(Op::kChannel), scratch_);
  channels_.push_back(std::move(c));
  if (out_.size() >= options_.buffer_bytes && !flush_buffer()) return 0xFFFF;
  return channels_.back().id;
}

bool McapWriter::write_message(std::uint16_t channel_id, std::uint64_t log_time_ns,
                               std::uint64_t publish_time_ns, std::span<const std::uint8_t> data) {
  if (failed_ || fd_ < 0) return false;
  if (channel_id == 0 || channel_id > channels_.size()) return false;
  Channel& ch = channels_[channel_id - 1U];
  ++ch.sequence;
  const std::uint64_t offset = chunk_.size();
  // Message: channel_id u16, sequence u32, log_time u64, publish_time u64, data (rest).
  const std::uint64_t len = 2 + 4 + 8 + 8 + data.size();
  put_u8(chunk_, static_cast<std::uint8_t>(Op::kMessage));
  put_u64(chunk_, len);
  put_u16(chunk_, channel_id);
  put_u32(chunk_, ch.sequence);
  put_u64(chunk_, log_time_ns);
  put_u64(chunk_, publish_time_ns);
  put_bytes(chunk_, data);
  chunk_index_[channel_id].emplace_back(log_time_ns, offset);
  if (chunk_messages_ == 0 || log_time_ns < chunk_start_ns_) chunk_start_ns_ = log_time_ns;
  if (chunk_messages_ == 0 || log_time_ns > chunk_end_ns_) chunk_end_ns_ = log_time_ns;
  if (stats_.messages == 0 || log_time_ns < message_start_ns_) message_start_ns_ = log_time_ns;
  if (stats_.messages == 0 || log_time_ns > message_end_ns_) message_end_ns_ = log_time_ns;
  ++chunk_messages_;
  ++stats_.messages;
  ++stats_.channel_message_counts[channel_id];
  if (chunk_.size() >= options_.chunk_size_bytes) return close_chunk();
  return true;
}

bool McapWriter::write_metadata(std::string_view name, const McapMetadataMap& values) {
  if (failed_ || fd_ < 0) return false;
  scratch_.clear();
  put_str(scratch_, name);
  put_str_map(scratch_, values);
  const std::uint64_t at = offset();
  emit_record(static_cast<std::uint8_t>(Op::kMetadata), scratch_);
  metadata_indexes_.push_back({at, offset() - at, std::string(name)});
  return out_.size() < options_.buffer_bytes || flush_buffer();
}

bool McapWriter::write_attachment(std::string_view name, std::string_view media_type,
                                  std::uint64_t log_time_ns, std::uint64_t create_time_ns,
                                  std::span<const std::uint8_t> data) {
  if (failed_ || fd_ < 0) return false;
  scratch_.clear();
  put_u64(scratch_, log_time_ns);
  put_u64(scratch_, create_time_ns);
  put_str(scratch_, name);
  put_str(scratch_, media_type);
  put_u64(scratch_, data.size());
  put_bytes(scratch_, data);
  put_u32(scratch_, crc32(scratch_));  // CRC of every preceding field of the record
  const std::uint64_t at = offset();
  emit_record(static_cast<std::uint8_t>(Op::kAttachment), scratch_);
  attachment_indexes_.push_back({at, offset() - at, log_time_ns, create_time_ns, data.size(),
                                 std::string(name), std::string(media_type)});
  return out_.size() < options_.buffer_bytes || flush_buffer();
}

bool McapWriter::close_chunk() {
  if (failed_ || fd_ < 0) return false;
  if (chunk_messages_ == 0) return flush_buffer() && sync_file();

  std::span<const std::uint8_t> records = chunk_;
  std::string_view compression;
  if (options_.compress && zstd_ != nullptr) {
    compressed_.resize(ZSTD_compressBound(chunk_.size()));
    const std::size_t n =
        ZSTD_compressCCtx(static_cast<ZSTD_CCtx*>(zstd_), compressed_.data(), compressed_.size(),
                          chunk_.data(), chunk_.size(), options_.zstd_level);
    if (ZSTD_isError(n) != 0U) {
      fail(std::string("zstd: ") + ZSTD_getErrorName(n), 0);
      return false;
    }
    records = std::span<const std::uint8_t>(compressed_.data(), n);
    compression = "zstd";
  }
  // Chunk: start u64, end u64, uncompressed_size u64, uncompressed_crc u32, compression string,
  // records (u64 length prefix).
  scratch_.clear();
  put_u64(scratch_, chunk_start_ns_);
  put_u64(scratch_, chunk_end_ns_);
  put_u64(scratch_, chunk_.size());
  put_u32(scratch_, crc32(chunk_));
  put_str(scratch_, compression);
  put_u64(scratch_, records.size());
  ChunkIndex index{chunk_start_ns_, chunk_end_ns_, offset(), 0, 0,
                   records.size(),  chunk_.size(), {}};
  // The chunk's prefix and fixed fields, then its records straight from the compressor output.
  std::uint8_t prefix[mcap::kRecordPrefixBytes];
  prefix[0] = static_cast<std::uint8_t>(Op::kChunk);
  const std::uint64_t len = scratch_.size() + records.size();
  for (std::size_t i = 0; i < 8; ++i) prefix[1 + i] = static_cast<std::uint8_t>(len >> (8 * i));
  emit(prefix);
  emit(scratch_);
  emit(records);
  index.chunk_length = offset() - index.chunk_offset;

  // MessageIndex per channel: channel_id u16, records Array<(log_time u64, offset u64)>.
  const std::uint64_t index_start = offset();
  for (const auto& [channel, entries] : chunk_index_) {
    scratch_.clear();
    put_u16(scratch_, channel);
    put_u32(scratch_, static_cast<std::uint32_t>(entries.size() * 16));
    for (const auto& [t, off] : entries) {
      put_u64(scratch_, t);
      put_u64(scratch_, off);
    }
    index.index_offsets.emplace_back(channel, offset());
    emit_record(static_cast<std::uint8_t>(Op::kMessageIndex), scratch_);
  }
  index.index_length = offset() - index_start;
  chunk_indexes_.push_back(std::move(index));

  ++stats_.chunks;
  stats_.uncompressed_chunk_bytes += chunk_.size();
  chunk_.clear();
  chunk_index_.clear();
  chunk_messages_ = 0;
  return flush_buffer() && sync_file();
}

bool McapWriter::close() {
  if (fd_ < 0) return !failed_;
  bool ok = close_chunk();
  if (ok) {
    // DataEnd: CRC-32 of every byte from the start of the file up to this record.
    const std::uint32_t data_crc = data_crc_;
    in_data_section_ = false;
    scratch_.clear();
    put_u32(scratch_, data_crc);
    emit_record(static_cast<std::uint8_t>(Op::kDataEnd), scratch_);

    const std::uint64_t summary_start = offset();
    const std::size_t summary_buffer_start = out_.size();
    struct Group {
      Op op;
      std::uint64_t start, length;
    };
    std::vector<Group> groups;
    auto group = [&](Op op, const auto& body) {
      const std::uint64_t start = offset();
      body();
      if (offset() > start) groups.push_back({op, start, offset() - start});
    };
    group(Op::kSchema, [&] {
      for (const auto& s : schemas_) {
        scratch_.clear();
        encode_schema(scratch_, s);
        emit_record(static_cast<std::uint8_t>(Op::kSchema), scratch_);
      }
    });
    group(Op::kChannel, [&] {
      for (const auto& c : channels_) {
        scratch_.clear();
        encode_channel(scratch_, c);
        emit_record(static_cast<std::uint8_t>(Op::kChannel), scratch_);
      }
    });
    group(Op::kStatistics, [&] {
      scratch_.clear();
      put_u64(scratch_, stats_.messages);
      put_u16(scratch_, static_cast<std::uint16_t>(schemas_.size()));
      put_u32(scratch_, static_cast<std::uint32_t>(channels_.size()));
      put_u32(scratch_, static_cast<std::uint32_t>(attachment_indexes_.size()));
      put_u32(scratch_, static_cast<std::uint32_t>(metadata_indexes_.size()));
      put_u32(scratch_, static_cast<std::uint32_t>(chunk_indexes_.size()));
      put_u64(scratch_, message_start_ns_);
      put_u64(scratch_, message_end_ns_);
      put_u32(scratch_, static_cast<std::uint32_t>(stats_.channel_message_counts.size() * 10));
      for (const auto& [channel, count] : stats_.channel_message_counts) {
        put_u16(scratch_, channel);
        put_u64(scratch_, count);
      }
      emit_record(static_cast<std::uint8_t>(Op::kStatistics), scratch_);
    });
    group(Op::kChunkIndex, [&] {
      for (const auto& ci : chunk_indexes_) {
        scratch_.clear();
        put_u64(scratch_, ci.start_ns);
        put_u64(scratch_, ci.end_ns);
        put_u64(scratch_, ci.chunk_offset);
        put_u64(scratch_, ci.chunk_length);
        put_u32(scratch_, static_cast<std::uint32_t>(ci.index_offsets.size() * 10));
        for (const auto& [channel, off] : ci.index_offsets) {
          put_u16(scratch_, channel);
          put_u64(scratch_, off);
        }
        put_u64(scratch_, ci.index_length);
        put_str(scratch_, options_.compress ? "zstd" : "");
        put_u64(scratch_, ci.compressed_size);
        put_u64(scratch_, ci.uncompressed_size);
        emit_record(static_cast<std::uint8_t>(Op::kChunkIndex), scratch_);
      }
    });
    group(Op::kAttachmentIndex, [&] {
      for (const auto& ai : attachment_indexes_) {
        scratch_.clear();
        put_u64(scratch_, ai.offset);
        put_u64(scratch_, ai.length);
        put_u64(scratch_, ai.log_time);
        put_u64(scratch_, ai.create_time);
        put_u64(scratch_, ai.data_size);
        put_str(scratch_, ai.name);
        put_str(scratch_, ai.media_type);
        emit_record(static_cast<std::uint8_t>(Op::kAttachmentIndex), scratch_);
      }
    });
    group(Op::kMetadataIndex, [&] {
      for (const auto& mi : metadata_indexes_) {
        scratch_.clear();
        put_u64(scratch_, mi.offset);
        put_u64(scratch_, mi.length);
        put_str(scratch_, mi.name);
        emit_record(static_cast<std::uint8_t>(Op::kMetadataIndex), scratch_);
      }
    });
    const std::uint64_t summary_offset_start = offset();
    for (const auto& g : groups) {
      scratch_.clear();
      put_u8(scratch_, static_cast<std::uint8_t>(g.op));
      put_u64(scratch_, g.start);
      put_u64(scratch_, g.length);
      emit_record(static_cast<std::uint8_t>(Op::kSummaryOffset), scratch_);
    }
    // Footer: summary_start u64, summary_offset_start u64, summary_crc u32, where the CRC covers
    // the summary start through the footer's summary_offset_start field.
    std::vector<std::uint8_t> footer;
    put_u8(footer, static_cast<std::uint8_t>(Op::kFooter));
    put_u64(footer, 8 + 8 + 4);
    put_u64(footer, summary_start);
    put_u64(footer, summary_offset_start);
    std::uint32_t summary_crc =
        crc32_update(0, std::span<const std::uint8_t>(out_).subspan(summary_buffer_start));
    summary_crc = crc32_update(summary_crc, footer);
    put_u32(footer, summary_crc);
    emit(footer);
    emit(mcap::kMagic);
    ok = flush_buffer() && sync_file();
  }
  ::close(fd_);
  fd_ = -1;
  closed_ = true;
  return ok && !failed_;
}

}  // namespace coxswain::record
