// SPDX-License-Identifier: Apache-2.0
// EmulatorHost and PseudoTerminal through real pseudo-terminals: the test plays the host side
// with plain POSIX calls on the slave, as a serial driver would.
#include "sim/pty/emulator_host.hpp"

#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <bit>
#include <chrono>
#include <filesystem>
#include <functional>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "sim/pty/pseudo_terminal.hpp"
#include "support/temp_dir.hpp"
#include "support/wait_for.hpp"

namespace coxswain::sim::pty {
namespace {

using coxswain::test::TempDir;
using coxswain::test::wait_for;

using namespace std::chrono_literals;

// A small line device written for these tests: every 10 ms it sends "$T,<n>\n" and it answers
// each line the host writes with "ECHO:<line>\n". It keeps a copy of all it sent, so the test
// can compare what arrived with what was sent.
class LineDevice final : public devices::DeviceEmulator {
 public:
  void receive(std::span<const std::uint8_t> host_bytes, core::TimeNs /*now_ns*/) override {
    for (const auto b : host_bytes) {
      if (b == '\n') {
        answers_ += "ECHO:" + line_ + "\n";
        line_.clear();
      } else {
        line_.push_back(static_cast<char>(b));
      }
    }
  }
  std::span<const std::uint8_t> poll(core::TimeNs now_ns) override {
    out_ = answers_;
    answers_.clear();
    if (next_ns_ == core::kNeverNs) next_ns_ = now_ns;
    while (now_ns >= next_ns_) {
      out_ += "$T," + std::to_string(count_++) + "\n";
      next_ns_ += 10 * core::kNsPerMs;
    }
    emitted += out_;
    return {reinterpret_cast<const std::uint8_t*>(out_.data()), out_.size()};
  }
  std::string emitted;

 private:
  std::string line_;
  std::string answers_;
  std::string out_;
  core::TimeNs next_ns_ = core::kNeverNs;
  std::uint64_t count_ = 0;
};

// The host's end: opens the slave in raw mode, non-blocking.
class HostPort {
 public:
  explicit HostPort(const std::string& path) {
    fd_ = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
    if (fd_ >= 0) {
      termios t{};
      ::tcgetattr(fd_, &t);
      ::cfmakeraw(&t);
      ::tcsetattr(fd_, TCSANOW, &t);
    }
  }
  ~HostPort() {
    if (fd_ >= 0) ::close(fd_);
  }
  [[nodiscard]] bool is_open() const { return fd_ >= 0; }
  void write(const std::string& s) const {
    ASSERT_EQ(::write(fd_, s.data(), s.size()), static_cast<ssize_t>(s.size()));
  }
  // Reads what is available within `timeout`; returns -1 on an error/EOF (unplug) and sets
  // `hung_up`.
  int read_some(std::string& into, std::chrono::milliseconds timeout) {
    pollfd p{fd_, POLLIN, 0};
    const int r = ::poll(&p, 1, static_cast<int>(timeout.count()));
    if (r <= 0) return 0;
    char buf[4096];
    const ssize_t n = ::read(fd_, buf, sizeof buf);
    if (n > 0) {
      into.append(buf, static_cast<std::size_t>(n));
      return static_cast<int>(n);
    }
    if (n < 0 && errno == EAGAIN) return 0;
    return -1;  // 0 = EOF or -1 = EIO: the master is gone
  }
  // Reads until `done(text)` or the deadline.
  bool read_until(std::string& into, const std::function<bool(const std::string&)>& done,
                  std::chrono::milliseconds timeout = 5000ms) {
    const auto end = std::chrono::steady_clock::now() + timeout;
    while (!done(into)) {
      if (std::chrono::steady_clock::now() > end) return false;
      if (read_some(into, 50ms) < 0) return false;
    }
    return true;
  }
  // Reads until nothing has arrived for `quiet`.
  void drain(std::string& into, std::chrono::milliseconds quiet = 200ms) {
    while (read_some(into, quiet) > 0) {
    }
  }

 private:
  int fd_ = -1;
};

EmulatorHost::Options options(std::filesystem::path link = {}, std::uint64_t seed = 1,
                              std::size_t max_pending_bytes = 64 * 1024,
                              core::TimeNs tick_ns = 2 * core::kNsPerMs) {
  EmulatorHost::Options o;
  o.link_path = std::move(link);
  o.seed = seed;
  o.max_pending_bytes = max_pending_bytes;
  o.tick_ns = tick_ns;
  return o;
}

bool contains(const std::string& text, const std::string& what) {
  return text.find(what) != std::string::npos;
}

TEST(PseudoTerminal, RawRoundTripAndSymlink) {
  TempDir dir;
  const auto link = dir.path() / "ttyTEST";
  PseudoTerminal pty(link);
  EXPECT_TRUE(std::filesystem::is_symlink(link));
  EXPECT_EQ(std::filesystem::read_symlink(link).string(), pty.slave_name());
  EXPECT_EQ(pty.device_path(), link.string());
  // Nothing to read yet, and no spurious hangup before the host opens the slave.
  std::array<std::uint8_t, 64> buf{};
  EXPECT_EQ(pty.read(buf), 0U);

  HostPort host(link.string());
  ASSERT_TRUE(host.is_open());
  // Raw mode: CR, NUL and 0xFF pass unchanged both ways.
  const std::string binary("\r\n\0\xff\x11\x13", 6);
  host.write(binary);
  std::string got;
  ASSERT_TRUE(wait_for([&] {
    const std::size_t n = pty.read(buf);
    got.append(reinterpret_cast<const char*>(buf.data()), n);
    return got.size() >= binary.size();
  }));
  EXPECT_EQ(got, binary);
  const auto* p = reinterpret_cast<const std::uint8_t*>(binary.data());
  EXPECT_EQ(pty.write({p, binary.size()}), binary.size());
  std::string back;
  ASSERT_TRUE(host.read_until(back, [&](const std::string& s) { return s.size() >= 6; }));
  EXPECT_EQ(back, binary);

  pty.unplug();
  EXPECT_FALSE(std::filesystem::exists(link));
  EXPECT_FALSE(pty.plugged());
  EXPECT_EQ(pty.write({p, binary.size()}), 0U);
}

TEST(EmulatorHost, RoundTripThroughARealPty) {
  TempDir dir;
  LineDevice device;
  EmulatorHost host(device, options(dir.path() / "ttyLINE"));
  HostPort port(host.device_path());
  ASSERT_TRUE(port.is_open());
  port.write("hello\n");
  std::string got;
  ASSERT_TRUE(
      port.read_until(got, [](const std::string& s) { return contains(s, "ECHO:hello\n"); }));
  EXPECT_TRUE(contains(got, "$T,"));
  const HostCounters c = host.counters();
  EXPECT_EQ(c.bytes_from_host, 6U);
  EXPECT_GT(c.bytes_to_host, 0U);
  EXPECT_EQ(c.garbage_bytes, 0U);
}

TEST(EmulatorHost, UnplugFailsTheHostAndReplugWorks) {
  TempDir dir;
  const auto link = dir.path() / "ttyLINE";
  LineDevice device;
  EmulatorHost host(device, options(link));
  {
    HostPort port(link.string());
    ASSERT_TRUE(port.is_open());
    std::string got;
    ASSERT_TRUE(port.read_until(got, [](const std::string& s) { return contains(s, "$T,"); }));

    host.unplug();
    EXPECT_FALSE(host.plugged());
    EXPECT_FALSE(std::filesystem::exists(link));
    // The host's open port now reports EOF/EIO instead of blocking forever.
    const auto end = std::chrono::steady_clock::now() + 5s;
    int r = 0;
    while ((r = port.read_some(got, 50ms)) >= 0 && std::chrono::steady_clock::now() < end) {
    }
    EXPECT_LT(r, 0) << "the host never saw the unplug";
    EXPECT_FALSE(HostPort(link.string()).is_open());
  }
  host.replug();
  ASSERT_TRUE(host.plugged());
  ASSERT_TRUE(std::filesystem::is_symlink(link));
  EXPECT_EQ(std::filesystem::read_symlink(link).string(), host.slave_name());
  HostPort port(link.string());
  ASSERT_TRUE(port.is_open());
  port.write("again\n");
  std::string got;
  ASSERT_TRUE(
      port.read_until(got, [](const std::string& s) { return contains(s, "ECHO:again\n"); }));
  const HostCounters c = host.counters();
  EXPECT_EQ(c.unplugs, 1U);
  EXPECT_EQ(c.replugs, 1U);
}

TEST(EmulatorHost, GarbageIsInsertedAndCounted) {
  LineDevice device;
  EmulatorHost host(device, options({}, 7));
  HostPort port(host.device_path());
  ASSERT_TRUE(port.is_open());
  host.set_garbage(1.0, 8);
  std::string got;
  ASSERT_TRUE(wait_for([&] {
    port.read_some(got, 10ms);
    return host.counters().garbage_bursts >= 5;
  }));
  host.stop();
  port.drain(got);
  const HostCounters c = host.counters();
  EXPECT_GE(c.garbage_bursts, 5U);
  EXPECT_GE(c.garbage_bytes, c.garbage_bursts);
  EXPECT_LE(c.garbage_bytes, 8 * c.garbage_bursts);
  // Everything the pty accepted reached the host: the device's bytes plus the garbage.
  EXPECT_EQ(got.size(), c.bytes_to_host);
  EXPECT_EQ(c.bytes_to_host, c.device_bytes + c.garbage_bytes);
  EXPECT_EQ(got.size(), host.locked([&] { return device.emitted.size(); }) + c.garbage_bytes);
}

TEST(EmulatorHost, CorruptionFlipsExactlyTheCountedBits) {
  LineDevice device;
  EmulatorHost host(device, options({}, 3));
  HostPort port(host.device_path());
  ASSERT_TRUE(port.is_open());
  host.set_corruption(0.05);
  std::string got;
  ASSERT_TRUE(wait_for([&] {
    port.read_some(got, 10ms);
    return host.counters().bits_flipped >= 20;
  }));
  host.stop();
  port.drain(got);
  const std::string sent = host.locked([&] { return device.emitted; });
  ASSERT_EQ(got.size(), sent.size());
  std::uint64_t differing_bits = 0;
  for (std::size_t i = 0; i < got.size(); ++i) {
    differing_bits += static_cast<std::uint64_t>(
        std::popcount(static_cast<unsigned>(static_cast<std::uint8_t>(got[i] ^ sent[i]))));
  }
  EXPECT_EQ(differing_bits, host.counters().bits_flipped);
}

TEST(EmulatorHost, SilentDeviceSendsNothing) {
  LineDevice device;
  EmulatorHost host(device, options());
  HostPort port(host.device_path());
  ASSERT_TRUE(port.is_open());
  std::string got;
  ASSERT_TRUE(port.read_until(got, [](const std::string& s) { return contains(s, "$T,"); }));
  host.set_silent(true);
  ASSERT_TRUE(wait_for([&] { return host.counters().silenced_bytes > 0; }));
  port.drain(got, 100ms);  // what was already in the pty
  const std::uint64_t silenced = host.counters().silenced_bytes;
  ASSERT_TRUE(wait_for([&] { return host.counters().silenced_bytes > silenced + 50; }));
  std::string later;
  EXPECT_EQ(port.read_some(later, 0ms), 0);
  EXPECT_TRUE(later.empty());
  host.set_silent(false);
  ASSERT_TRUE(port.read_until(later, [](const std::string& s) { return contains(s, "$T,"); }));
}

TEST(EmulatorHost, OutputNobodyReadsIsBoundedAndCounted) {
  LineDevice device;
  EmulatorHost host(device, options({}, 1, 256));
  host.set_garbage(1.0, 4096);  // fills the pty's buffer quickly
  ASSERT_TRUE(wait_for([&] { return host.counters().overflow_bytes > 0; }));
  host.stop();
  const HostCounters c = host.counters();
  // Every byte produced was either accepted by the pty, dropped, or still waits (at most the
  // bound) in the host's buffer.
  const std::uint64_t produced = c.device_bytes + c.garbage_bytes;
  ASSERT_GE(produced, c.bytes_to_host + c.overflow_bytes);
  EXPECT_LE(produced - c.bytes_to_host - c.overflow_bytes, 256U);
}

TEST(EmulatorHost, StopIsPrompt) {
  LineDevice device;
  EmulatorHost host(device, options({}, 1, 64 * 1024, core::kNsPerSec));
  const auto t0 = std::chrono::steady_clock::now();
  host.stop();
  EXPECT_LT(std::chrono::steady_clock::now() - t0, 500ms);
}

}  // namespace
}  // namespace coxswain::sim::pty
