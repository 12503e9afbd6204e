// SPDX-License-Identifier: Apache-2.0
// RtcmSource against real inputs: a TCP server in this test (with a disconnect and a
// reconnect), a regular file larger than the queue, and a named pipe whose writer comes and goes.
// Good frames must arrive whole and in order; frames with a bad CRC must be counted and dropped.
#include "coxswain/drivers/ublox/rtcm_source.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/write.hpp>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <mutex>
#include <string>
#include <string_view>
#include <thread>
#include <utility>
#include <vector>

#include "coxswain/drivers/ublox/codec.hpp"

namespace coxswain::drivers::ublox {
namespace {

namespace asio = boost::asio;
using Bytes = std::vector<std::uint8_t>;

Bytes rtcm_frame(std::uint16_t type, std::size_t payload_len, std::uint8_t seed) {
  Bytes f{kRtcm3Preamble, static_cast<std::uint8_t>(payload_len >> 8),
          static_cast<std::uint8_t>(payload_len & 0xFF)};
  for (std::size_t i = 0; i < payload_len; ++i) {
    f.push_back(static_cast<std::uint8_t>(seed + i * 13));
  }
  f[3] = static_cast<std::uint8_t>(type >> 4);
  f[4] = static_cast<std::uint8_t>(((type & 0x0F) << 4) | (f[4] & 0x0F));
  const std::uint32_t crc = crc24q(f);
  f.push_back(static_cast<std::uint8_t>(crc >> 16));
  f.push_back(static_cast<std::uint8_t>(crc >> 8));
  f.push_back(static_cast<std::uint8_t>(crc));
  return f;
}

/// Pops frames until `want` arrived or `timeout` passed (polling: the queue has no wait).
std::vector<Bytes> drain(RtcmQueue& q, std::size_t want, std::chrono::seconds timeout) {
  std::vector<Bytes> got;
  const auto end = std::chrono::steady_clock::now() + timeout;
  while (got.size() < want && std::chrono::steady_clock::now() < end) {
    if (const auto* s = q.front()) {
      got.emplace_back(s->view().begin(), s->view().end());
      q.release();
    } else {
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
  }
  return got;
}

bool wait_until(const std::function<bool()>& cond, std::chrono::seconds timeout) {
  const auto end = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < end) {
    if (cond()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return cond();
}

TEST(RtcmSource, ParsesTcpAddresses) {
  std::string host, port;
  EXPECT_TRUE(RtcmSource::parse_tcp("tcp://127.0.0.1:2101", host, port));
  EXPECT_EQ(host, "127.0.0.1");
  EXPECT_EQ(port, "2101");
  EXPECT_TRUE(RtcmSource::parse_tcp("tcp://[::1]:5000", host, port));
  EXPECT_EQ(host, "::1");
  EXPECT_FALSE(RtcmSource::parse_tcp("tcp://host", host, port));
  EXPECT_FALSE(RtcmSource::parse_tcp("tcp://host:", host, port));
  EXPECT_FALSE(RtcmSource::parse_tcp("tcp://host:x1", host, port));
  EXPECT_FALSE(RtcmSource::parse_tcp("corrections/base.rtcm3", host, port));
}

TEST(RtcmSource, EmptyInputStartsNothing) {
  RtcmQueue q;
  RtcmSource src("", q);
  src.start();
  src.stop();
  EXPECT_EQ(src.stats().connects, 0U);
}

TEST(RtcmSource, TcpFramesBadCrcDroppedAndReconnectAfterServerCloses) {
  asio::io_context io;
  asio::ip::tcp::acceptor acceptor(io, {asio::ip::make_address("127.0.0.1"), 0});
  const auto port = acceptor.local_endpoint().port();
  const Bytes a = rtcm_frame(1005, 19, 1);
  const Bytes b = rtcm_frame(1077, 400, 2);
  Bytes bad = rtcm_frame(1087, 100, 3);
  bad[50] ^= 0xFF;
  const Bytes c = rtcm_frame(1230, 8, 4);

  RtcmQueue q;
  RtcmSourceOptions opt;
  opt.backoff_initial_ns = 20 * core::kNsPerMs;
  opt.backoff_max_ns = 200 * core::kNsPerMs;
  RtcmSource src("tcp://127.0.0.1:" + std::to_string(port), q, opt);
  src.start();

  {  // First connection: a, garbage, bad, b (split in two writes), then close.
    asio::ip::tcp::socket peer(io);
    acceptor.accept(peer);
    Bytes stream = a;
    stream.insert(stream.end(), {0x00, 0x42, 0x99});
    stream.insert(stream.end(), bad.begin(), bad.end());
    stream.insert(stream.end(), b.begin(), b.begin() + 200);
    asio::write(peer, asio::buffer(stream));
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    asio::write(peer, asio::buffer(b.data() + 200, b.size() - 200));
    const auto got = drain(q, 2, std::chrono::seconds(10));
    ASSERT_EQ(got.size(), 2U);
    EXPECT_EQ(got[0], a);
    EXPECT_EQ(got[1], b);
  }  // peer closed: the source must reconnect
  {
    asio::ip::tcp::socket peer(io);
    acceptor.accept(peer);  // blocks until the reconnect
    asio::write(peer, asio::buffer(c));
    const auto got = drain(q, 1, std::chrono::seconds(10));
    ASSERT_EQ(got.size(), 1U);
    EXPECT_EQ(got[0], c);
  }
  src.stop();
  const auto st = src.stats();
  EXPECT_EQ(st.frames_ok, 3U);
  EXPECT_EQ(st.frames_queued, 3U);
  EXPECT_GE(st.crc_errors, 1U);
  EXPECT_EQ(st.connects, 2U);
  EXPECT_GE(st.failures, 1U);
}

TEST(RtcmSource, TcpRetriesWhileNoServerListens) {
  // Find a free port, then close it so the connection is refused.
  asio::io_context io;
  std::uint16_t port = 0;
  {
    asio::ip::tcp::acceptor probe(io, {asio::ip::make_address("127.0.0.1"), 0});
    port = probe.local_endpoint().port();
  }
  RtcmQueue q;
  RtcmSourceOptions opt;
  opt.backoff_initial_ns = 10 * core::kNsPerMs;
  opt.backoff_max_ns = 50 * core::kNsPerMs;
  RtcmSource src("tcp://127.0.0.1:" + std::to_string(port), q, opt);
  src.start();
  EXPECT_TRUE(wait_until([&] { return src.stats().failures >= 3; }, std::chrono::seconds(10)));
  // Now a server appears on that port: the source connects.
  asio::ip::tcp::acceptor acceptor(io, {asio::ip::make_address("127.0.0.1"), port});
  asio::ip::tcp::socket peer(io);
  acceptor.accept(peer);
  const Bytes a = rtcm_frame(1005, 19, 9);
  asio::write(peer, asio::buffer(a));
  const auto got = drain(q, 1, std::chrono::seconds(10));
  ASSERT_EQ(got.size(), 1U);
  EXPECT_EQ(got[0], a);
  src.stop();
}

// A refused connection is told once however often it is retried, and the recovery once.
TEST(RtcmSource, ARefusedConnectionIsToldOnceAndTheRecoveryOnce) {
  asio::io_context io;
  std::uint16_t port = 0;
  {
    asio::ip::tcp::acceptor probe(io, {asio::ip::make_address("127.0.0.1"), 0});
    port = probe.local_endpoint().port();
  }
  RtcmQueue q;
  std::mutex mutex;
  std::vector<std::pair<bool, std::string>> events;
  RtcmSourceOptions opt;
  opt.backoff_initial_ns = 10 * core::kNsPerMs;
  opt.backoff_max_ns = 20 * core::kNsPerMs;
  opt.on_event = [&](bool problem, std::string_view what) {
    const std::lock_guard<std::mutex> lock(mutex);
    events.emplace_back(problem, std::string(what));
  };
  RtcmSource src("tcp://127.0.0.1:" + std::to_string(port), q, opt);
  src.start();
  ASSERT_TRUE(wait_until([&] { return src.stats().failures >= 5; }, std::chrono::seconds(10)));
  asio::ip::tcp::acceptor acceptor(io, {asio::ip::make_address("127.0.0.1"), port});
  asio::ip::tcp::socket peer(io);
  acceptor.accept(peer);
  ASSERT_TRUE(wait_until([&] { return src.stats().connects >= 1; }, std::chrono::seconds(10)));
  src.stop();
  const std::lock_guard<std::mutex> lock(mutex);
  ASSERT_EQ(events.size(), 2U);
  EXPECT_TRUE(events[0].first);
  EXPECT_NE(events[0].second.find("cannot connect to 127.0.0.1:" + std::to_string(port)),
            std::string::npos)
      << events[0].second;
  EXPECT_FALSE(events[1].first);
  EXPECT_NE(events[1].second.find("connected"), std::string::npos) << events[1].second;
}

std::filesystem::path temp_path(const std::string& name) {
  return std::filesystem::temp_directory_path() /
         ("coxswain_rtcm_" + std::to_string(::getpid()) + "_" + name);
}

TEST(RtcmSource, FileIsReadOnceWithoutDropsEvenWhenLargerThanTheQueue) {
  const auto path = temp_path("file.rtcm3");
  std::vector<Bytes> frames;
  {
    std::ofstream out(path, std::ios::binary);
    for (int i = 0; i < 200; ++i) {
      frames.push_back(rtcm_frame(static_cast<std::uint16_t>(1074 + i % 4),
                                  static_cast<std::size_t>(30 + i), static_cast<std::uint8_t>(i)));
      out.write(reinterpret_cast<const char*>(frames.back().data()),
                static_cast<std::streamsize>(frames.back().size()));
      if (i == 100) {
        Bytes bad = rtcm_frame(1005, 19, 0);
        bad.back() ^= 1;
        out.write(reinterpret_cast<const char*>(bad.data()),
                  static_cast<std::streamsize>(bad.size()));
      }
    }
  }
  RtcmQueue q;
  RtcmSource src(path.string(), q);
  src.start();
  const auto got = drain(q, frames.size(), std::chrono::seconds(20));
  EXPECT_TRUE(wait_until([&] { return src.stats().finished; }, std::chrono::seconds(10)));
  src.stop();
  std::filesystem::remove(path);
  ASSERT_EQ(got.size(), frames.size());
  EXPECT_EQ(got, frames);
  EXPECT_EQ(src.stats().frames_dropped, 0U);
  EXPECT_EQ(src.stats().crc_errors, 1U);
  EXPECT_EQ(drain(q, 1, std::chrono::seconds(0)).size(), 0U);
}

TEST(RtcmSource, MissingFileIsReportedNotFatal) {
  RtcmQueue q;
  RtcmSource src(temp_path("absent").string(), q);
  src.start();
  EXPECT_TRUE(wait_until([&] { return src.stats().finished; }, std::chrono::seconds(10)));
  EXPECT_EQ(src.stats().failures, 1U);
  src.stop();
}

TEST(RtcmSource, NamedPipeIsReopenedWhenItsWriterComesBack) {
  const auto path = temp_path("pipe");
  std::filesystem::remove(path);
  ASSERT_EQ(::mkfifo(path.c_str(), 0600), 0);
  RtcmQueue q;
  RtcmSourceOptions opt;
  opt.backoff_initial_ns = 10 * core::kNsPerMs;
  opt.backoff_max_ns = 50 * core::kNsPerMs;
  RtcmSource src(path.string(), q, opt);
  src.start();
  const Bytes a = rtcm_frame(1005, 19, 5);
  const Bytes b = rtcm_frame(1097, 250, 6);
  std::uint64_t eofs = 0;
  for (const Bytes* f : {&a, &b}) {
    // The previous writer's EOF was seen (counted as a failure) before the next writer opens.
    ASSERT_TRUE(wait_until([&] { return src.stats().failures > eofs; }, std::chrono::seconds(10)) ||
                eofs == 0);
    eofs = src.stats().failures;
    // Opening for writing blocks until the source has the pipe open for reading.
    std::ofstream w(path, std::ios::binary);
    ASSERT_TRUE(w.good());
    w.write(reinterpret_cast<const char*>(f->data()), static_cast<std::streamsize>(f->size()));
    w.flush();
    const auto got = drain(q, 1, std::chrono::seconds(10));
    ASSERT_EQ(got.size(), 1U);
    EXPECT_EQ(got[0], *f);
  }  // each writer closes: EOF, the source reopens
  EXPECT_TRUE(wait_until([&] { return src.stats().failures > eofs; }, std::chrono::seconds(10)));
  src.stop();
  std::filesystem::remove(path);
  EXPECT_GE(src.stats().connects, 2U);
}

}  // namespace
}  // namespace coxswain::drivers::ublox
