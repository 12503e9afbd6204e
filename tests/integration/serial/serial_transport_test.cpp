// SPDX-License-Identifier: Apache-2.0
// SerialTransport end to end: a real session (the test line protocol) over real pseudo-terminals
// served by EmulatorHost, with unplug, garbage, corruption, silence and a full write queue.
#include "coxswain/drivers/serial/serial_transport.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "line_protocol.hpp"
#include "sim/pty/emulator_host.hpp"
#include "support/temp_dir.hpp"
#include "support/wait_for.hpp"

namespace coxswain::drivers::serial {
namespace {

using coxswain::test::TempDir;
using coxswain::test::wait_for;

using namespace std::chrono_literals;
using test::LineDevice;
using test::LineSession;
using test::LineSessionOptions;

// Collects what a transport tees (a stand-in for the recorder; a mutex is fine in a test).
class CollectingSink final : public RawByteSink {
 public:
  void on_raw(msg::DeviceId /*device*/, RawDirection direction, core::TimeNs /*stamp_ns*/,
              std::span<const std::uint8_t> bytes) noexcept override {
    std::lock_guard<std::mutex> lock(mutex_);
    auto& into = direction == RawDirection::kFromDevice ? from_device_ : to_device_;
    into.append(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  }
  [[nodiscard]] std::string from_device() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return from_device_;
  }
  [[nodiscard]] std::string to_device() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return to_device_;
  }

 private:
  mutable std::mutex mutex_;
  std::string from_device_;
  std::string to_device_;
};

sim::pty::EmulatorHost::Options host_options(const std::filesystem::path& link,
                                             std::uint64_t seed = 1) {
  sim::pty::EmulatorHost::Options o;
  o.link_path = link;
  o.seed = seed;
  return o;
}

config::SerialDeviceConfig port_config(const std::filesystem::path& path) {
  config::SerialDeviceConfig c;
  c.path = path.string();
  c.baud = 115200;
  c.timeout_ms = 300;
  return c;
}

msg::DeviceHealth health_of(const core::LatestSlot<msg::DeviceHealth>& slot) {
  return slot.read().value;
}

TEST(SerialTransport, DataFlowsWithArrivalStampsAndWritesReachTheDevice) {
  TempDir dir;
  LineDevice device;
  sim::pty::EmulatorHost host(device, host_options(dir / "ttyLINE"));
  LineSessionOptions so;
  so.writes_on_open = {"hello\n"};
  LineSession session(so);
  core::LatestSlot<msg::DeviceHealth> health;
  const core::SteadyClock clock;
  CollectingSink sink;
  const core::TimeNs t0 = clock.now_ns();
  SerialTransport transport(port_config(dir / "ttyLINE"), session, health, clock, &sink);
  transport.start();

  ASSERT_TRUE(wait_for([&] { return session.frame_count() >= 50; }));
  ASSERT_TRUE(wait_for([&] { return !session.echoes().empty(); }));
  ASSERT_TRUE(wait_for([&] { return health_of(health).state == msg::DeviceState::kRunning; }));
  transport.stop();
  EXPECT_FALSE(transport.running());
  const core::TimeNs t1 = clock.now_ns();

  EXPECT_EQ(session.echoes(), std::vector<std::string>{"hello"});
  EXPECT_EQ(session.write_results(), std::vector<bool>{true});
  EXPECT_EQ(sink.to_device(), "hello\n");

  const auto frames = session.frames();
  std::vector<core::TimeNs> latencies;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    EXPECT_GE(frames[i].stamp_ns, t0);
    EXPECT_LE(frames[i].stamp_ns, t1);
    // A frame is stamped when its first byte arrived: never before the device produced it.
    EXPECT_GE(frames[i].stamp_ns, frames[i].emit_ns);
    if (i > 0) {
      EXPECT_GE(frames[i].stamp_ns, frames[i - 1].stamp_ns);
    }
    latencies.push_back(frames[i].stamp_ns - frames[i].emit_ns);
  }
  const auto middle = latencies.begin() + static_cast<std::ptrdiff_t>(latencies.size() / 2);
  std::nth_element(latencies.begin(), middle, latencies.end());
  RecordProperty("median_stamp_latency_us", static_cast<int>(*middle / core::kNsPerUs));
  EXPECT_LT(*middle, 50 * core::kNsPerMs);  // typically < 1 ms

  const TransportCounters c = transport.counters();
  EXPECT_EQ(c.opens, 1U);
  EXPECT_EQ(c.reopen_count, 0U);
  EXPECT_EQ(c.bytes_written, 6U);
  EXPECT_EQ(c.bytes_received, sink.from_device().size());
  const msg::DeviceHealth h = health_of(health);
  EXPECT_EQ(h.device, msg::DeviceId::kGnss);
  EXPECT_GT(h.bytes_received, 0U);
  EXPECT_LE(h.bytes_received, c.bytes_received);
  EXPECT_GT(h.frames_ok, 0U);  // published at ~10 Hz: it may lag the last frames
  EXPECT_LE(h.frames_ok, frames.size());
  EXPECT_EQ(session.opens(), 1);
  EXPECT_EQ(session.closes(), 1);  // stop() closes the port through the session
}

TEST(SerialTransport, GarbageAndCorruptionPassThroughToTheSession) {
  TempDir dir;
  LineDevice device;
  sim::pty::EmulatorHost host(device, host_options(dir / "ttyLINE", 11));
  host.set_garbage(0.3, 16);
  host.set_corruption(0.003);
  LineSession session;
  core::LatestSlot<msg::DeviceHealth> health;
  const core::SteadyClock clock;
  CollectingSink sink;
  SerialTransport transport(port_config(dir / "ttyLINE"), session, health, clock, &sink);
  transport.start();
  ASSERT_TRUE(wait_for([&] {
    const msg::DeviceHealth h = health_of(health);
    return h.frames_ok >= 100 && h.framing_errors > 0 && h.checksum_errors > 0;
  }));
  transport.stop();
  host.stop();
  // Every byte read went, unchanged, to the raw sink; no more arrived than the pty carried.
  EXPECT_EQ(transport.counters().bytes_received, sink.from_device().size());
  EXPECT_LE(transport.counters().bytes_received, host.counters().bytes_to_host);
  EXPECT_GT(host.counters().garbage_bursts, 0U);
  EXPECT_GT(host.counters().bits_flipped, 0U);
}

TEST(SerialTransport, UnplugGivesAbsentThenDataResumesAfterReplug) {
  TempDir dir;
  const auto link = dir / "ttyLINE";
  LineDevice device;
  sim::pty::EmulatorHost host(device, host_options(link));
  LineSession session;
  core::LatestSlot<msg::DeviceHealth> health;
  const core::SteadyClock clock;
  SerialTransport transport(port_config(link), session, health, clock);
  transport.start();
  ASSERT_TRUE(wait_for([&] { return session.frame_count() >= 10; }));

  host.unplug();
  ASSERT_TRUE(wait_for([&] { return health_of(health).state == msg::DeviceState::kAbsent; }));
  const msg::DeviceHealth absent = health_of(health);
  EXPECT_NE(absent.detail_text().find(link.string()), std::string_view::npos)
      << absent.detail_text();
  EXPECT_EQ(session.closes(), 1);
  EXPECT_GE(transport.counters().closes, 1U);
  const std::size_t before = session.frame_count();

  host.replug();  // a new /dev/pts/N behind the same link
  ASSERT_TRUE(wait_for([&] { return session.frame_count() >= before + 10; }));
  ASSERT_TRUE(wait_for([&] { return health_of(health).state == msg::DeviceState::kRunning; }));
  const TransportCounters c = transport.counters();
  EXPECT_EQ(c.reopen_count, 1U);
  EXPECT_EQ(health_of(health).reopen_count, 1U);
  EXPECT_EQ(session.opens(), 2);
  transport.stop();
}

TEST(SerialTransport, AbsentPathIsRetriedWithBackoffNotABusyLoop) {
  TempDir dir;
  const auto link = dir / "ttyLATE";
  LineSession session;
  core::LatestSlot<msg::DeviceHealth> health;
  const core::SteadyClock clock;
  SerialTransport transport(port_config(link), session, health, clock);
  transport.start();
  ASSERT_TRUE(wait_for([&] { return health_of(health).state == msg::DeviceState::kAbsent; }));
  const msg::DeviceHealth h = health_of(health);
  EXPECT_NE(h.detail_text().find(link.string()), std::string_view::npos) << h.detail_text();
  EXPECT_NE(h.detail_text().find("No such file"), std::string_view::npos) << h.detail_text();
  // Tries at 0, 100, 300, 700 ms...: a measurement of the retry rate, not a synchronisation.
  std::this_thread::sleep_for(800ms);
  const std::uint64_t failures = transport.counters().open_failures;
  EXPECT_GE(failures, 2U);
  EXPECT_LE(failures, 6U);

  LineDevice device;
  sim::pty::EmulatorHost host(device, host_options(link));
  ASSERT_TRUE(wait_for([&] { return session.frame_count() >= 10; }));
  EXPECT_EQ(transport.counters().opens, 1U);
  EXPECT_EQ(transport.counters().reopen_count, 0U);
  transport.stop();
}

TEST(SerialTransport, StopIsPromptWhileSilentOrUnplugged) {
  TempDir dir;
  LineDevice device;
  sim::pty::EmulatorHost host(device, host_options(dir / "ttyLINE"));
  host.set_silent(true);
  LineSession session;
  core::LatestSlot<msg::DeviceHealth> health;
  const core::SteadyClock clock;
  {
    SerialTransport transport(port_config(dir / "ttyLINE"), session, health, clock);
    transport.start();
    ASSERT_TRUE(wait_for([&] { return transport.counters().opens == 1; }));
    ASSERT_TRUE(
        wait_for([&] { return health_of(health).state == msg::DeviceState::kConfiguring; }));
    const auto t0 = std::chrono::steady_clock::now();
    transport.stop();
    const auto took = std::chrono::steady_clock::now() - t0;
    RecordProperty(
        "stop_silent_us",
        static_cast<int>(std::chrono::duration_cast<std::chrono::microseconds>(took).count()));
    EXPECT_LT(took, 100ms) << "stop() with a silent device took "
                           << std::chrono::duration<double, std::milli>(took).count() << " ms";
  }
  {
    SerialTransport transport(port_config(dir / "ttyNONE"), session, health, clock);
    transport.start();
    ASSERT_TRUE(wait_for([&] { return transport.counters().open_failures >= 3; }));
    const auto t0 = std::chrono::steady_clock::now();
    transport.stop();  // while waiting out a backoff
    const auto took = std::chrono::steady_clock::now() - t0;
    RecordProperty(
        "stop_absent_us",
        static_cast<int>(std::chrono::duration_cast<std::chrono::microseconds>(took).count()));
    EXPECT_LT(took, 100ms) << "stop() with an absent device took "
                           << std::chrono::duration<double, std::milli>(took).count() << " ms";
  }
}

TEST(SerialTransport, SessionReopenVerdictReopensWithBackoff) {
  TempDir dir;
  LineDevice device;
  sim::pty::EmulatorHost host(device, host_options(dir / "ttyLINE"));
  LineSessionOptions so;
  so.reopen_after_silence_ns = 50 * core::kNsPerMs;
  LineSession session(so);
  core::LatestSlot<msg::DeviceHealth> health;
  const core::SteadyClock clock;
  SerialTransport transport(port_config(dir / "ttyLINE"), session, health, clock);
  transport.start();
  ASSERT_TRUE(wait_for([&] { return session.frame_count() >= 5; }));
  host.set_silent(true);
  ASSERT_TRUE(wait_for([&] { return transport.counters().reopen_count >= 3; }));
  // Silence after each reopen doubles the wait (100, 200, 400 ms...), so reopens stay rare.
  const auto t0 = std::chrono::steady_clock::now();
  const std::uint32_t r0 = transport.counters().reopen_count;
  std::this_thread::sleep_for(1s);  // measuring the reopen rate
  const std::uint32_t reopens = transport.counters().reopen_count - r0;
  EXPECT_LE(reopens, 5U) << "in " << (std::chrono::steady_clock::now() - t0).count() << " ns";
  host.set_silent(false);
  const std::size_t before = session.frame_count();
  ASSERT_TRUE(wait_for([&] { return session.frame_count() >= before + 10; }));
  EXPECT_EQ(session.opens(), static_cast<int>(transport.counters().opens));
  transport.stop();
}

TEST(SerialTransport, FullWriteQueueDropsAndCounts) {
  TempDir dir;
  LineDevice device;
  sim::pty::EmulatorHost host(device, host_options(dir / "ttyLINE"));
  LineSessionOptions so;
  const std::string line = std::string(49, 'A') + "\n";
  // The first write goes out at once (in flight), the second waits in the 64-byte queue, the
  // third does not fit: all three happen inside on_open, before any write can complete.
  so.writes_on_open = {line, line, line};
  LineSession session(so);
  core::LatestSlot<msg::DeviceHealth> health;
  const core::SteadyClock clock;
  TransportOptions options;
  options.write_queue_bytes = 64;
  SerialTransport transport(port_config(dir / "ttyLINE"), session, health, clock, nullptr, options);
  transport.start();
  ASSERT_TRUE(wait_for([&] { return session.echoes().size() >= 2; }));
  ASSERT_TRUE(wait_for([&] { return session.frame_count() >= 20; }));  // no third echo coming
  transport.stop();
  EXPECT_EQ(session.write_results(), (std::vector<bool>{true, true, false}));
  EXPECT_EQ(session.echoes().size(), 2U);
  const TransportCounters c = transport.counters();
  EXPECT_EQ(c.writes_dropped, 1U);
  EXPECT_EQ(c.bytes_dropped, 50U);
  EXPECT_EQ(c.bytes_written, 100U);
}

TEST(SerialTransport, AStalledDeviceDoesNotDelayAnother) {
  TempDir dir;
  LineDevice good_device;
  LineDevice bad_device;
  sim::pty::EmulatorHost good_host(good_device, host_options(dir / "ttyGOOD"));
  sim::pty::EmulatorHost bad_host(bad_device, host_options(dir / "ttyBAD"));
  LineSessionOptions good_opts;
  good_opts.device = msg::DeviceId::kImu;
  LineSessionOptions bad_opts;
  bad_opts.device = msg::DeviceId::kGnss;
  bad_opts.reopen_after_silence_ns = 20 * core::kNsPerMs;
  LineSession good(good_opts);
  LineSession bad(bad_opts);
  core::LatestStore store;
  const core::SteadyClock clock;
  SerialTransport good_transport(port_config(dir / "ttyGOOD"), good, store.health_of(good.device()),
                                 clock);
  SerialTransport bad_transport(port_config(dir / "ttyBAD"), bad, store.health_of(bad.device()),
                                clock);
  good_transport.start();
  bad_transport.start();
  ASSERT_TRUE(wait_for([&] { return good.frame_count() >= 10 && bad.frame_count() >= 10; }));

  // The bad device goes silent, then is unplugged, then comes back garbled; the good one keeps
  // delivering through each phase.
  const std::size_t first = good.frame_count();
  const auto good_moves_on = [&good] {
    const std::size_t before = good.frame_count();
    return wait_for([&] { return good.frame_count() >= before + 5; });
  };
  bad_host.set_silent(true);
  ASSERT_TRUE(wait_for([&] { return bad_transport.counters().reopen_count >= 1; }));
  EXPECT_TRUE(good_moves_on());
  bad_host.unplug();
  ASSERT_TRUE(wait_for([&] { return bad_transport.counters().open_failures >= 2; }));
  EXPECT_TRUE(good_moves_on());
  bad_host.set_silent(false);
  bad_host.set_garbage(1.0, 64);
  bad_host.replug();
  ASSERT_TRUE(wait_for([&] { return good.frame_count() >= first + 100; }));
  good_transport.stop();
  bad_transport.stop();

  const auto frames = good.frames();
  core::TimeNs worst_gap_ns = 0;
  core::TimeNs worst_latency_ns = 0;
  for (std::size_t i = first + 1; i < frames.size(); ++i) {
    worst_gap_ns = std::max(worst_gap_ns, frames[i].stamp_ns - frames[i - 1].stamp_ns);
    worst_latency_ns = std::max(worst_latency_ns, frames[i].stamp_ns - frames[i].emit_ns);
  }
  // 100 Hz frames, typically a few ms apart. The bound is generous on purpose: it catches a
  // transport blocked behind the other device (seconds: backoff, a blocking open), not the
  // scheduling noise of a loaded machine running ThreadSanitizer (up to ~1 s seen).
  EXPECT_LT(worst_gap_ns, 1500 * core::kNsPerMs);
  EXPECT_LT(worst_latency_ns, 1500 * core::kNsPerMs);
  EXPECT_EQ(good_transport.counters().closes, 1U);  // only stop()
  EXPECT_EQ(good_transport.counters().reopen_count, 0U);
}

}  // namespace
}  // namespace coxswain::drivers::serial
