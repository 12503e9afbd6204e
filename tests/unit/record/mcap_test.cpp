// SPDX-License-Identifier: Apache-2.0
// McapWriter / McapReader: every record type round trip, CRCs, zstd, indexes, crash truncation at
// every byte, and write errors (ENOSPC through /dev/full).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "coxswain/record/crc32.hpp"
#include "coxswain/record/mcap_reader.hpp"
#include "coxswain/record/mcap_writer.hpp"

namespace coxswain::record {
namespace {

namespace fs = std::filesystem;

fs::path temp_path(const std::string& name) {
  return fs::temp_directory_path() / ("coxswain_mcap_" + std::to_string(::getpid()) + "_" + name);
}

std::vector<std::uint8_t> read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Offset of the first chunk record (opcode 0x06), walking records from after the magic.
std::size_t first_chunk_at(const std::vector<std::uint8_t>& bytes) {
  std::size_t at = 8;
  while (at + 9 <= bytes.size() && bytes[at] != 0x06) {
    std::uint64_t len = 0;
    for (std::size_t i = 0; i < 8; ++i) len |= std::uint64_t{bytes[at + 1 + i]} << (8 * i);
    at += 9 + len;
  }
  return at;
}

std::span<const std::uint8_t> bytes_of(const std::string& s) {
  return {reinterpret_cast<const std::uint8_t*>(s.data()), s.size()};
}

struct Written {
  std::uint16_t channel;
  std::uint64_t t;
  std::string data;
};

struct Got {
  std::uint16_t channel;
  std::uint32_t sequence;
  std::uint64_t t;
  std::string data;
  bool operator==(const Got&) const = default;
};

std::vector<Got> read_all(McapReader& reader, McapReadReport& report) {
  std::vector<Got> got;
  report = reader.read([&](const McapMessageView& m) {
    got.push_back({m.channel_id, m.sequence, m.log_time_ns,
                   std::string(reinterpret_cast<const char*>(m.data.data()), m.data.size())});
  });
  return got;
}

TEST(Crc32, KnownVectors) {
  EXPECT_EQ(crc32(bytes_of("123456789")), 0xCBF43926U);
  EXPECT_EQ(crc32({}), 0U);
  const std::string s = "The quick brown fox jumps over the lazy dog";
  EXPECT_EQ(crc32(bytes_of(s)), 0x414FA339U);
  // Incremental at every split point equals the one-shot CRC.
  for (std::size_t cut = 0; cut <= s.size(); ++cut) {
    const auto all = bytes_of(s);
    EXPECT_EQ(crc32_update(crc32(all.first(cut)), all.subspan(cut)), 0x414FA339U);
  }
}

class McapRoundTrip : public ::testing::TestWithParam<bool> {};

TEST_P(McapRoundTrip, EveryRecordTypeReadsBackWithValidCrcsAndIndexes) {
  const bool compress = GetParam();
  const fs::path path = temp_path(compress ? "rt_zstd.mcap" : "rt_plain.mcap");
  McapWriterOptions opt;
  opt.compress = compress;
  opt.chunk_size_bytes = 2000;  // several chunks closed by size
  opt.profile = "coxswain";
  McapWriter w(opt);
  ASSERT_TRUE(w.open(path)) << w.error();
  const auto s1 = w.add_schema("test.A", "jsonschema", std::string_view(R"({"type":"object"})"));
  const auto s2 = w.add_schema("test.B", "coxswain-layout", std::string_view("u8 x"));
  ASSERT_EQ(s1, 1);
  ASSERT_EQ(s2, 2);
  const auto c1 = w.add_channel(s1, "/a", "json", {{"k", "v"}});
  const auto c2 = w.add_channel(s2, "/b", "coxswain-binary");
  const auto c3 = w.add_channel(0, "/c", "raw");
  std::vector<Written> written;
  for (int i = 0; i < 300; ++i) {
    const std::uint16_t ch = i % 3 == 0 ? c1 : (i % 3 == 1 ? c2 : c3);
    const std::string data =
        "{\"i\":" + std::to_string(i) + std::string(static_cast<std::size_t>(i % 17), 'x') + "}";
    const std::uint64_t t = std::uint64_t{1000000} * static_cast<std::uint64_t>(i);
    ASSERT_TRUE(w.write_message(ch, t, t, bytes_of(data)));
    written.push_back({ch, t, data});
    if (i == 150) {
      ASSERT_TRUE(w.close_chunk());
    }
  }
  ASSERT_TRUE(w.write_metadata("config", {{"yaml", "a: 1\n"}, {"version", "0.1.0"}}));
  const std::string att = "attachment body";
  ASSERT_TRUE(w.write_attachment("notes.txt", "text/plain", 5, 6, bytes_of(att)));
  ASSERT_TRUE(w.close()) << w.error();
  EXPECT_GE(w.stats().chunks, 3U);
  EXPECT_EQ(w.stats().messages, 300U);

  McapReader reader;
  ASSERT_TRUE(reader.open(path));
  McapReadReport report;
  const auto got = read_all(reader, report);
  EXPECT_TRUE(report.error.empty()) << report.error;
  EXPECT_TRUE(report.header_ok);
  EXPECT_EQ(report.profile, "coxswain");
  EXPECT_EQ(report.library, "coxswain");
  EXPECT_TRUE(report.complete);
  EXPECT_FALSE(report.truncated);
  EXPECT_TRUE(report.data_crc_ok);
  EXPECT_TRUE(report.summary_crc_ok);
  EXPECT_TRUE(report.index_ok);
  EXPECT_EQ(report.chunk_crc_errors, 0U);
  EXPECT_EQ(report.chunks, w.stats().chunks);
  EXPECT_EQ(report.chunk_index_records, w.stats().chunks);
  EXPECT_GE(report.message_indexes, 3U);
  EXPECT_GE(report.summary_offsets, 5U);
  ASSERT_EQ(got.size(), written.size());
  std::map<std::uint16_t, std::uint32_t> seq;
  for (std::size_t i = 0; i < got.size(); ++i) {
    EXPECT_EQ(got[i].channel, written[i].channel);
    EXPECT_EQ(got[i].t, written[i].t);
    EXPECT_EQ(got[i].data, written[i].data);
    EXPECT_EQ(got[i].sequence, ++seq[got[i].channel]);
  }
  ASSERT_TRUE(report.statistics.has_value());
  EXPECT_EQ(report.statistics->message_count, 300U);
  EXPECT_EQ(report.statistics->schema_count, 2U);
  EXPECT_EQ(report.statistics->channel_count, 3U);
  EXPECT_EQ(report.statistics->metadata_count, 1U);
  EXPECT_EQ(report.statistics->attachment_count, 1U);
  EXPECT_EQ(report.statistics->chunk_count, w.stats().chunks);
  EXPECT_EQ(report.statistics->message_start_ns, 0U);
  EXPECT_EQ(report.statistics->message_end_ns, 299'000'000U);
  EXPECT_EQ(report.statistics->channel_message_counts.at(c1), 100U);
  EXPECT_EQ(report.statistics->channel_message_counts.at(c3), 100U);
  EXPECT_EQ(report.metadata.at("config").at("yaml"), "a: 1\n");
  ASSERT_EQ(report.attachments.size(), 1U);
  EXPECT_TRUE(report.attachments[0].crc_ok);
  EXPECT_EQ(std::string(report.attachments[0].data.begin(), report.attachments[0].data.end()), att);
  ASSERT_EQ(reader.channels().size(), 3U);
  EXPECT_EQ(reader.channels().at(c1).metadata.at("k"), "v");
  EXPECT_EQ(reader.schemas().at(s2).encoding, "coxswain-layout");
  EXPECT_EQ(reader.channel_id("/b"), c2);
  fs::remove(path);
}

INSTANTIATE_TEST_SUITE_P(Compression, McapRoundTrip, ::testing::Values(true, false));

TEST(McapWriter, ZstdCompressesChunks) {
  const fs::path path = temp_path("zstd.mcap");
  McapWriter w;
  ASSERT_TRUE(w.open(path));
  const auto ch = w.add_channel(0, "/zeros", "raw");
  const std::vector<std::uint8_t> zeros(10000, 0);
  for (int i = 0; i < 100; ++i)
    ASSERT_TRUE(w.write_message(ch, static_cast<std::uint64_t>(i), 0, zeros));
  ASSERT_TRUE(w.close());
  EXPECT_LT(fs::file_size(path), 100000U);  // 1 MB of zeros
  McapReader r;
  ASSERT_TRUE(r.open(path));
  std::size_t n = 0;
  const auto report = r.read([&](const McapMessageView& m) {
    EXPECT_EQ(m.data.size(), zeros.size());
    ++n;
  });
  EXPECT_EQ(n, 100U);
  EXPECT_TRUE(report.complete && report.data_crc_ok && report.summary_crc_ok && report.index_ok);
  fs::remove(path);
}

TEST(McapReader, DetectsCorruptedChunkAndDataSection) {
  const fs::path path = temp_path("corrupt.mcap");
  McapWriterOptions opt;
  opt.compress = false;
  McapWriter w(opt);
  ASSERT_TRUE(w.open(path));
  const auto ch = w.add_channel(0, "/x", "raw");
  const std::string payload = "PAYLOAD-0123456789";
  ASSERT_TRUE(w.write_message(ch, 1, 1, bytes_of(payload)));
  ASSERT_TRUE(w.close());
  auto bytes = read_file(path);
  const auto at = std::search(bytes.begin(), bytes.end(), payload.begin(), payload.end());
  ASSERT_NE(at, bytes.end());
  *at ^= 0x01;
  McapReader r;
  r.load(bytes);
  McapReadReport report;
  const auto got = read_all(r, report);
  EXPECT_EQ(report.chunk_crc_errors, 1U);
  EXPECT_FALSE(report.data_crc_ok);
  EXPECT_TRUE(got.empty());
  EXPECT_NE(report.error.find("CRC"), std::string::npos) << report.error;
  fs::remove(path);
}

// A corrupt chunk header may claim gigabytes; the reader refuses it before allocating.
TEST(McapReader, ChunkClaimingAHugeUncompressedSizeIsSkippedWithoutAllocatingIt) {
  for (const bool compress : {true, false}) {
    const fs::path path = temp_path("huge_chunk.mcap");
    McapWriterOptions opt;
    opt.compress = compress;
    McapWriter w(opt);
    ASSERT_TRUE(w.open(path));
    const auto ch = w.add_channel(0, "/x", "raw");
    ASSERT_TRUE(w.write_message(ch, 1, 1, bytes_of("PAYLOAD")));
    ASSERT_TRUE(w.close());
    auto bytes = read_file(path);
    const std::size_t at = first_chunk_at(bytes);
    ASSERT_LT(at + 9 + 24, bytes.size());
    const std::uint64_t huge = std::uint64_t{3} << 30U;  // 3 GiB
    for (std::size_t i = 0; i < 8; ++i) {
      bytes[at + 9 + 16 + i] = static_cast<std::uint8_t>(huge >> (8 * i));
    }
    McapReader r;
    r.load(bytes);
    McapReadReport report;
    const auto got = read_all(r, report);
    EXPECT_TRUE(got.empty()) << "compress=" << compress;
    EXPECT_EQ(report.chunk_crc_errors, 1U) << "compress=" << compress;
    EXPECT_FALSE(report.error.empty());
    fs::remove(path);
  }
}

// A compressed chunk claiming more bytes than its frames hold is refused, however the claim
// compares with the frames' own header (the reader grows its buffer with what zstd produces).
TEST(McapReader, CompressedChunkWhoseFramesFallShortOfItsClaimIsRefused) {
  for (const std::uint64_t extra :
       {std::uint64_t{1}, std::uint64_t{1000}, std::uint64_t{1} << 20U}) {
    const fs::path path = temp_path("short_chunk.mcap");
    McapWriterOptions opt;
    opt.compress = true;
    McapWriter w(opt);
    ASSERT_TRUE(w.open(path));
    const auto ch = w.add_channel(0, "/x", "raw");
    for (int i = 0; i < 200; ++i) {
      ASSERT_TRUE(w.write_message(ch, static_cast<std::uint64_t>(i + 1), 1,
                                  bytes_of("PAYLOAD-" + std::to_string(i))));
    }
    ASSERT_TRUE(w.close());
    auto bytes = read_file(path);
    const std::size_t at = first_chunk_at(bytes);
    ASSERT_LT(at + 9 + 24, bytes.size());
    std::uint64_t claimed = 0;
    for (std::size_t i = 0; i < 8; ++i) claimed |= std::uint64_t{bytes[at + 9 + 16 + i]} << (8 * i);
    claimed += extra;
    for (std::size_t i = 0; i < 8; ++i) {
      bytes[at + 9 + 16 + i] = static_cast<std::uint8_t>(claimed >> (8 * i));
    }
    McapReader r;
    r.load(bytes);
    McapReadReport report;
    const auto got = read_all(r, report);
    EXPECT_TRUE(got.empty()) << extra;
    EXPECT_EQ(report.chunk_crc_errors, 1U) << extra;
    EXPECT_NE(report.error.find("size mismatch"), std::string::npos) << report.error;
    fs::remove(path);
  }
}

TEST(McapReader, TruncationAtEveryByteRecoversEveryCompleteChunk) {
  const fs::path path = temp_path("trunc.mcap");
  McapWriter w;
  ASSERT_TRUE(w.open(path));
  const auto ch = w.add_channel(w.add_schema("s", "coxswain-layout", std::string_view("x")), "/t",
                                "coxswain-binary");
  // (bytes on disk after a chunk close, messages in closed chunks)
  std::vector<std::pair<std::uint64_t, std::size_t>> flush_points{{w.stats().bytes_written, 0}};
  std::vector<Written> written;
  for (int i = 0; i < 60; ++i) {
    const std::string data = "message " + std::to_string(i);
    ASSERT_TRUE(w.write_message(ch, static_cast<std::uint64_t>(i), 0, bytes_of(data)));
    written.push_back({ch, static_cast<std::uint64_t>(i), data});
    if (i % 10 == 9) {
      ASSERT_TRUE(w.close_chunk());
      flush_points.emplace_back(w.stats().bytes_written, written.size());
    }
  }
  ASSERT_TRUE(w.close());
  const auto full = read_file(path);
  for (std::size_t cut = 0; cut < full.size(); ++cut) {
    McapReader r;
    r.load(
        std::vector<std::uint8_t>(full.begin(), full.begin() + static_cast<std::ptrdiff_t>(cut)));
    McapReadReport report;
    const auto got = read_all(r, report);
    ASSERT_TRUE(report.truncated) << "cut " << cut;
    ASSERT_FALSE(report.complete);
    ASSERT_EQ(report.chunk_crc_errors, 0U) << "cut " << cut;
    // Everything flushed before the cut is recovered; at most the next chunk beyond it.
    std::size_t lower = 0;
    std::size_t upper = 0;
    for (const auto& [bytes, messages] : flush_points) {
      if (bytes <= cut) lower = messages;
      upper = messages;
      if (bytes > cut) break;
    }
    ASSERT_GE(got.size(), lower) << "cut " << cut;
    ASSERT_LE(got.size(), upper) << "cut " << cut;
    for (std::size_t i = 0; i < got.size(); ++i) ASSERT_EQ(got[i].data, written[i].data);
  }
  fs::remove(path);
}

TEST(McapWriter, DiskFullAtOpenFailsWithoutThrowing) {
  const int fd = ::open("/dev/full", O_WRONLY | O_CLOEXEC);
  if (fd < 0) GTEST_SKIP() << "/dev/full is not available";
  McapWriter w;
  EXPECT_FALSE(w.open_fd(fd, "/dev/full"));
  EXPECT_TRUE(w.failed());
  EXPECT_NE(w.error().find("No space left"), std::string::npos) << w.error();
  EXPECT_EQ(w.add_channel(0, "/x", "raw"), 0xFFFF);
  EXPECT_FALSE(w.write_message(1, 0, 0, {}));
  EXPECT_FALSE(w.close_chunk());
  EXPECT_FALSE(w.close());
}

TEST(McapWriter, DiskFullMidRunStopsAndKeepsWhatWasWritten) {
  const int devfull = ::open("/dev/full", O_WRONLY | O_CLOEXEC);
  if (devfull < 0) GTEST_SKIP() << "/dev/full is not available";
  const fs::path path = temp_path("full.mcap");
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  ASSERT_GE(fd, 0);
  McapWriter w;
  ASSERT_TRUE(w.open_fd(fd, path.string()));
  const auto ch = w.add_channel(0, "/x", "raw");
  const std::string data = "before the disk filled";
  for (int i = 0; i < 5; ++i)
    ASSERT_TRUE(w.write_message(ch, static_cast<std::uint64_t>(i), 0, bytes_of(data)));
  ASSERT_TRUE(w.close_chunk());
  // The disk fills up: the writer's descriptor now refuses every byte with ENOSPC.
  ASSERT_EQ(::dup2(devfull, fd), fd);
  ::close(devfull);
  EXPECT_TRUE(w.write_message(ch, 10, 0, bytes_of(data)));  // buffered in the open chunk
  EXPECT_FALSE(w.close_chunk());
  EXPECT_TRUE(w.failed());
  EXPECT_NE(w.error().find("No space left"), std::string::npos) << w.error();
  EXPECT_FALSE(w.write_message(ch, 11, 0, bytes_of(data)));
  EXPECT_FALSE(w.close());
  McapReader r;
  ASSERT_TRUE(r.open(path));
  McapReadReport report;
  const auto got = read_all(r, report);
  EXPECT_EQ(got.size(), 5U);
  EXPECT_TRUE(report.truncated);
  fs::remove(path);
}

}  // namespace
}  // namespace coxswain::record
