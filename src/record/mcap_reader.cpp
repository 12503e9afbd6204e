// SPDX-License-Identifier: Apache-2.0
#include "coxswain/record/mcap_reader.hpp"

#include <zstd.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <memory>

#include "coxswain/record/bytes.hpp"
#include "coxswain/record/crc32.hpp"
#include "coxswain/record/mcap.hpp"

namespace coxswain::record {
namespace {

using mcap::Op;

std::string get_str(ByteReader& r) {
  const std::uint32_t n = r.u32();
  const auto b = r.bytes(n);
  return {reinterpret_cast<const char*>(b.data()), b.size()};
}

std::map<std::string, std::string> get_str_map(ByteReader& r) {
  std::map<std::string, std::string> m;
  const std::uint32_t len = r.u32();
  ByteReader sub(r.bytes(len));
  while (sub.remaining() > 0 && !sub.underrun()) {
    std::string k = get_str(sub);
    std::string v = get_str(sub);
    if (sub.underrun()) break;
    m.emplace(std::move(k), std::move(v));
  }
  if (sub.underrun()) r.bytes(r.remaining() + 1);  // propagate the error
  return m;
}

std::uint64_t le64(std::span<const std::uint8_t> b) {
  std::uint64_t v = 0;
  for (std::size_t i = 0; i < 8; ++i) v |= static_cast<std::uint64_t>(b[i]) << (8 * i);
  return v;
}

// The writer closes a chunk at a few MiB; a single camera frame may push one past that.
constexpr std::uint64_t kMaxChunkBytes = std::uint64_t{256} << 20U;
// zstd's best case is a 128 KiB run-length block in 4 bytes; no real chunk compresses further.
constexpr std::uint64_t kMaxZstdRatio = 32768;

struct ChunkFields {
  std::uint64_t start_ns = 0, end_ns = 0, uncompressed_size = 0;
  std::uint32_t uncompressed_crc = 0;
  std::string compression;
  std::span<const std::uint8_t> records;
};

bool parse_chunk(std::span<const std::uint8_t> content, ChunkFields& c) {
  ByteReader r(content);
  c.start_ns = r.u64();
  c.end_ns = r.u64();
  c.uncompressed_size = r.u64();
  c.uncompressed_crc = r.u32();
  c.compression = get_str(r);
  const std::uint64_t n = r.u64();
  if (r.underrun() || n > r.remaining()) return false;
  c.records = r.bytes(static_cast<std::size_t>(n));
  return !r.underrun();
}

/// Decompresses every zstd frame of `in` into `out`, which must come to exactly `expected`
/// bytes. The output grows with what the frames really produce, never to the size the header
/// claims up front: a small corrupt chunk claiming a large size costs no large allocation.
std::string decompress_zstd(std::span<const std::uint8_t> in, std::uint64_t expected,
                            std::vector<std::uint8_t>& out) {
  constexpr std::size_t kFirstBytes = std::size_t{64} << 10U;
  const std::unique_ptr<ZSTD_DCtx, std::size_t (*)(ZSTD_DCtx*)> ctx(ZSTD_createDCtx(),
                                                                    &ZSTD_freeDCtx);
  if (!ctx) return "zstd: out of memory";
  const auto cap = static_cast<std::size_t>(expected);
  out.resize(std::min(cap, std::max(kFirstBytes, in.size() * 4)));
  ZSTD_inBuffer src{in.data(), in.size(), 0};
  std::size_t produced = 0;
  for (;;) {
    ZSTD_outBuffer dst{out.data(), out.size(), produced};
    const std::size_t ret = ZSTD_decompressStream(ctx.get(), &dst, &src);
    if (ZSTD_isError(ret) != 0U) return std::string("zstd: ") + ZSTD_getErrorName(ret);
    produced = dst.pos;
    if (ret == 0 && src.pos == src.size) break;  // the last frame is complete
    if (produced == out.size()) {
      if (out.size() == cap) {
        // Full at the declared size: finished only if zstd has nothing more to give.
        std::uint8_t probe = 0;
        ZSTD_outBuffer one{&probe, 1, 0};
        const std::size_t more = ZSTD_decompressStream(ctx.get(), &one, &src);
        if (ZSTD_isError(more) != 0U) return std::string("zstd: ") + ZSTD_getErrorName(more);
        if (one.pos != 0) return "chunk uncompressed size mismatch";
        if (more == 0 && src.pos == src.size) break;
        if (src.pos == src.size) return "zstd: truncated frame";
        continue;
      }
      out.resize(std::min(cap, out.size() * 2));
    } else if (src.pos == src.size) {
      return "zstd: truncated frame";  // room to write, nothing left to read, frame unfinished
    }
  }
  if (produced != cap) return "chunk uncompressed size mismatch";
  out.resize(produced);
  return {};
}

/// Decompresses (or copies) a chunk's records and checks its CRC. Empty string = success.
std::string unpack_chunk(const ChunkFields& c, std::vector<std::uint8_t>& out) {
  // A chunk's sizes come from the file: check them against what the bytes can hold before
  // allocating, so a corrupt header cannot ask for gigabytes.
  if (c.uncompressed_size > kMaxChunkBytes) return "chunk too large";
  if (c.compression.empty() && c.records.size() != c.uncompressed_size) {
    return "chunk uncompressed size mismatch";
  }
  if (c.compression == "zstd") {
    const unsigned long long framed = ZSTD_getFrameContentSize(c.records.data(), c.records.size());
    if (framed == ZSTD_CONTENTSIZE_ERROR) return "zstd: not a zstd frame";
    // Only the first frame's size is known here; a chunk may hold several frames.
    if (framed != ZSTD_CONTENTSIZE_UNKNOWN && framed > c.uncompressed_size) {
      return "chunk uncompressed size mismatch";
    }
    if (c.uncompressed_size > c.records.size() * kMaxZstdRatio) return "chunk too large";
  }
  if (c.compression == "zstd") {
    std::string err = decompress_zstd(c.records, c.uncompressed_size, out);
    if (!err.empty()) return err;
  } else if (c.compression.empty()) {
    out.assign(c.records.begin(), c.records.end());
  } else {
    return "unsupported chunk compression '" + c.compression + "'";
  }
  if (c.uncompressed_crc != 0 && crc32(out) != c.uncompressed_crc) return "chunk CRC mismatch";
  return {};
}

}  // namespace

bool McapReader::open(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  bytes_.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  return !in.bad();
}

void McapReader::load(std::vector<std::uint8_t> bytes) { bytes_ = std::move(bytes); }

std::optional<std::uint16_t> McapReader::channel_id(const std::string& topic) const {
  for (const auto& [id, c] : channels_) {
    if (c.topic == topic) return id;
  }
  return std::nullopt;
}

McapReadReport McapReader::read(const MessageFn& on_message) {
  McapReadReport report;
  schemas_.clear();
  channels_.clear();
  chunk_indexes_.clear();
  summary_offsets_.clear();
  summary_start_ = 0;
  const std::span<const std::uint8_t> file(bytes_);
  if (file.size() < mcap::kMagic.size() ||
      !std::equal(mcap::kMagic.begin(), mcap::kMagic.end(), file.begin())) {
    report.error = "not an MCAP file (bad magic)";
    report.truncated = file.size() < mcap::kMagic.size();
    return report;
  }
  read_records(file.subspan(mcap::kMagic.size()), false, mcap::kMagic.size(), on_message, report);
  if (report.complete) verify_indexes(report);
  return report;
}

bool McapReader::read_records(std::span<const std::uint8_t> records, bool in_chunk,
                              std::uint64_t base, const MessageFn& on_message,
                              McapReadReport& report) {
  std::size_t pos = 0;
  bool footer_seen = false;
  auto malformed = [&](const std::string& what) {
    if (report.error.empty()) report.error = what + " at offset " + std::to_string(base + pos);
    return false;
  };
  while (pos < records.size()) {
    const std::size_t left = records.size() - pos;
    if (!in_chunk && footer_seen) {
      report.complete = left == mcap::kMagic.size() &&
                        std::equal(mcap::kMagic.begin(), mcap::kMagic.end(),
                                   records.begin() + static_cast<std::ptrdiff_t>(pos));
      if (!report.complete) {
        report.truncated = left < mcap::kMagic.size();
        if (!report.truncated) return malformed("bytes after the closing magic");
      }
      return true;
    }
    if (left < mcap::kRecordPrefixBytes) {
      if (in_chunk) return malformed("partial record in chunk");
      report.truncated = true;
      return true;
    }
    const auto op = static_cast<Op>(records[pos]);
    const std::uint64_t len = le64(records.subspan(pos + 1, 8));
    if (len > left - mcap::kRecordPrefixBytes) {
      if (in_chunk) return malformed("record overruns its chunk");
      report.truncated = true;
      return true;
    }
    const std::uint64_t record_offset = base + pos;
    const auto content =
        records.subspan(pos + mcap::kRecordPrefixBytes, static_cast<std::size_t>(len));
    ByteReader r(content);
    switch (op) {
      case Op::kHeader:
        report.profile = get_str(r);
        report.library = get_str(r);
        report.header_ok = !r.underrun() && record_offset == mcap::kMagic.size();
        break;
      case Op::kSchema: {
        McapSchemaInfo s;
        s.id = r.u16();
        s.name = get_str(r);
        s.encoding = get_str(r);
        const std::uint32_t n = r.u32();
        const auto d = r.bytes(n);
        s.data.assign(d.begin(), d.end());
        if (r.underrun()) return malformed("bad Schema");
        schemas_[s.id] = std::move(s);
        break;
      }
      case Op::kChannel: {
        McapChannelInfo c;
        c.id = r.u16();
        c.schema_id = r.u16();
        c.topic = get_str(r);
        c.message_encoding = get_str(r);
        c.metadata = get_str_map(r);
        if (r.underrun()) return malformed("bad Channel");
        channels_[c.id] = std::move(c);
        break;
      }
      case Op::kMessage: {
        McapMessageView m;
        m.channel_id = r.u16();
        m.sequence = r.u32();
        m.log_time_ns = r.u64();
        m.publish_time_ns = r.u64();
        if (r.underrun()) return malformed("bad Message");
        m.data = r.bytes(r.remaining());
        ++report.messages;
        if (on_message) on_message(m);
        break;
      }
      case Op::kChunk: {
        if (in_chunk) return malformed("chunk inside a chunk");
        ChunkFields c;
        if (!parse_chunk(content, c)) return malformed("bad Chunk");
        const std::string err = unpack_chunk(c, decompressed_);
        ++report.chunks;
        if (!err.empty()) {
          ++report.chunk_crc_errors;
          if (report.error.empty())
            report.error = err + " at offset " + std::to_string(record_offset);
          break;
        }
        std::vector<std::uint8_t> inner;
        inner.swap(decompressed_);
        if (!read_records(inner, true, 0, on_message, report)) return false;
        break;
      }
      case Op::kMessageIndex:
        ++report.message_indexes;
        break;
      case Op::kChunkIndex: {
        ChunkIndexEntry e{};
        r.u64();
        r.u64();
        e.chunk_offset = r.u64();
        e.chunk_length = r.u64();
        ByteReader offsets(r.bytes(r.u32()));
        while (offsets.remaining() >= 10) {
          const std::uint16_t ch = offsets.u16();
          e.index_offsets[ch] = offsets.u64();
        }
        e.index_length = r.u64();
        if (r.underrun()) return malformed("bad ChunkIndex");
        chunk_indexes_.push_back(std::move(e));
        ++report.chunk_index_records;
        break;
      }
      case Op::kAttachment: {
        McapAttachmentInfo a;
        a.log_time_ns = r.u64();
        r.u64();
        a.name = get_str(r);
        a.media_type = get_str(r);
        const std::uint64_t n = r.u64();
        if (r.underrun() || n > r.remaining()) return malformed("bad Attachment");
        const auto d = r.bytes(static_cast<std::size_t>(n));
        a.data.assign(d.begin(), d.end());
        const std::size_t covered = r.pos();
        const std::uint32_t crc = r.u32();
        if (r.underrun()) return malformed("bad Attachment");
        a.crc_ok = crc == 0 || crc == crc32(content.first(covered));
        report.attachments.push_back(std::move(a));
        break;
      }
      case Op::kStatistics: {
        McapStatisticsInfo s;
        s.message_count = r.u64();
        s.schema_count = r.u16();
        s.channel_count = r.u32();
        s.attachment_count = r.u32();
        s.metadata_count = r.u32();
        s.chunk_count = r.u32();
        s.message_start_ns = r.u64();
        s.message_end_ns = r.u64();
        ByteReader counts(r.bytes(r.u32()));
        while (counts.remaining() >= 10) {
          const std::uint16_t ch = counts.u16();
          s.channel_message_counts[ch] = counts.u64();
        }
        if (r.underrun()) return malformed("bad Statistics");
        report.statistics = std::move(s);
        break;
      }
      case Op::kMetadata: {
        std::string name = get_str(r);
        auto values = get_str_map(r);
        if (r.underrun()) return malformed("bad Metadata");
        report.metadata[std::move(name)] = std::move(values);
        break;
      }
      case Op::kSummaryOffset: {
        SummaryOffsetEntry e{};
        e.op = r.u8();
        e.start = r.u64();
        e.length = r.u64();
        if (r.underrun()) return malformed("bad SummaryOffset");
        summary_offsets_.push_back(e);
        ++report.summary_offsets;
        break;
      }
      case Op::kDataEnd: {
        const std::uint32_t crc = r.u32();
        report.data_crc_ok = crc == 0 || crc == crc32(std::span<const std::uint8_t>(bytes_).first(
                                                    static_cast<std::size_t>(record_offset)));
        summary_start_ = record_offset + mcap::kRecordPrefixBytes + len;
        break;
      }
      case Op::kFooter: {
        const std::uint64_t summary_start = r.u64();
        r.u64();
        const std::uint32_t crc = r.u32();
        if (r.underrun()) return malformed("bad Footer");
        const std::uint64_t crc_end = record_offset + mcap::kRecordPrefixBytes + 16;
        if (summary_start == 0) {
          report.summary_crc_ok = crc == 0;
        } else if (summary_start <= crc_end) {
          report.summary_crc_ok =
              crc == 0 || crc == crc32(std::span<const std::uint8_t>(bytes_).subspan(
                                     static_cast<std::size_t>(summary_start),
                                     static_cast<std::size_t>(crc_end - summary_start)));
        }
        footer_seen = true;
        break;
      }
      default:
        break;  // MetadataIndex, AttachmentIndex and unknown opcodes carry nothing we need
    }
    pos += mcap::kRecordPrefixBytes + static_cast<std::size_t>(len);
  }
  if (!in_chunk) report.truncated = true;  // ended without footer and magic
  return true;
}

void McapReader::verify_indexes(McapReadReport& report) {
  const std::span<const std::uint8_t> file(bytes_);
  auto record_at = [&](std::uint64_t off, Op op) -> std::span<const std::uint8_t> {
    if (off + mcap::kRecordPrefixBytes > file.size() ||
        file[off] != static_cast<std::uint8_t>(op)) {
      return {};
    }
    const std::uint64_t len = le64(file.subspan(static_cast<std::size_t>(off) + 1, 8));
    if (len > file.size() - off - mcap::kRecordPrefixBytes) return {};
    return file.subspan(static_cast<std::size_t>(off),
                        static_cast<std::size_t>(len) + mcap::kRecordPrefixBytes);
  };
  bool ok = summary_start_ != 0;
  for (const auto& ci : chunk_indexes_) {
    const auto chunk = record_at(ci.chunk_offset, Op::kChunk);
    ChunkFields c;
    std::vector<std::uint8_t> records;
    if (chunk.size() != ci.chunk_length ||
        !parse_chunk(chunk.subspan(mcap::kRecordPrefixBytes), c) ||
        !unpack_chunk(c, records).empty()) {
      ok = false;
      continue;
    }
    std::uint64_t index_bytes = 0;
    for (const auto& [channel, off] : ci.index_offsets) {
      const auto mi = record_at(off, Op::kMessageIndex);
      if (mi.empty()) {
        ok = false;
        continue;
      }
      index_bytes += mi.size();
      ByteReader r(mi.subspan(mcap::kRecordPrefixBytes));
      ok = ok && r.u16() == channel;
      ByteReader entries(r.bytes(r.u32()));
      while (entries.remaining() >= 16) {
        const std::uint64_t t = entries.u64();
        const std::uint64_t at = entries.u64();
        // Message: opcode, length, channel_id u16, sequence u32, log_time u64.
        if (at + mcap::kRecordPrefixBytes + 14 > records.size() ||
            records[at] != static_cast<std::uint8_t>(Op::kMessage)) {
          ok = false;
          break;
        }
        ByteReader m(std::span<const std::uint8_t>(records).subspan(at + mcap::kRecordPrefixBytes));
        const std::uint16_t ch = m.u16();
        m.u32();
        ok = ok && ch == channel && m.u64() == t;
      }
    }
    ok = ok && index_bytes == ci.index_length;
  }
  for (const auto& so : summary_offsets_) {
    ok = ok && so.start + so.length <= file.size() && so.start < file.size() &&
         file[so.start] == so.op;
  }
  report.index_ok = ok;
}

}  // namespace coxswain::record
