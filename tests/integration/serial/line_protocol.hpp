// SPDX-License-Identifier: Apache-2.0
#pragma once
// A small NMEA-like line protocol written for the transport tests, with a device emulator core
// and a DeviceSession for it, so the transport is exercised by a real session over a real pty.
//   device -> host:  "$T,<seq>,<emit_ns>*HH\n" every 10 ms (HH = XOR of the bytes between '$'
//                    and '*', two hex digits), and "ECHO:<line>\n" for each line the host wrote.
#include <cstdio>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

#include "coxswain/drivers/device_session.hpp"
#include "sim/devices/device_emulator.hpp"

namespace coxswain::test {

inline std::string checksummed(const std::string& body) {
  unsigned cs = 0;
  for (const char c : body) cs ^= static_cast<unsigned char>(c);
  char hex[4];
  std::snprintf(hex, sizeof hex, "%02X", cs);
  return "$" + body + "*" + hex + "\n";
}

class LineDevice final : public sim::devices::DeviceEmulator {
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
    if (now_ns - next_ns_ > 100 * core::kNsPerMs) next_ns_ = now_ns;  // no catch-up bursts
    while (now_ns >= next_ns_) {
      out_ += checksummed("T," + std::to_string(seq_++) + "," + std::to_string(now_ns));
      next_ns_ += 10 * core::kNsPerMs;
    }
    return {reinterpret_cast<const std::uint8_t*>(out_.data()), out_.size()};
  }

 private:
  std::string line_;
  std::string answers_;
  std::string out_;
  core::TimeNs next_ns_ = core::kNeverNs;
  std::uint64_t seq_ = 0;
};

struct ReceivedLine {
  std::string text;           // without the newline
  core::TimeNs stamp_ns = 0;  // arrival of the chunk holding its first byte
  core::TimeNs emit_ns = 0;   // for "$T" lines: when the device produced it
};

struct LineSessionOptions {
  msg::DeviceId device = msg::DeviceId::kGnss;
  core::TimeNs stale_after_ns = 300 * core::kNsPerMs;
  core::TimeNs reopen_after_silence_ns = 0;  // > 0: ask for a reopen after this much silence
  std::vector<std::string> writes_on_open;   // written in on_open, results recorded
};

/// Session for the line protocol. Called on the transport's thread; the test reads what it
/// recorded through the accessors, which lock (the test's only shared state).
class LineSession final : public drivers::DeviceSession {
 public:
  explicit LineSession(LineSessionOptions options = {}) : options_(std::move(options)) {}

  [[nodiscard]] msg::DeviceId device() const override { return options_.device; }

  void on_open(drivers::DeviceLink& link, core::TimeNs now_ns) override {
    std::lock_guard<std::mutex> lock(mutex_);
    ++opens_;
    open_ns_ = now_ns;
    partial_.clear();
    state_ = msg::DeviceState::kConfiguring;
    for (const std::string& w : options_.writes_on_open) {
      write_results_.push_back(
          link.write({reinterpret_cast<const std::uint8_t*>(w.data()), w.size()}));
    }
    link.set_dtr(false);  // fails on a pty: the transport must shrug it off
  }

  void on_bytes(std::span<const std::uint8_t> bytes, core::TimeNs arrival_ns,
                drivers::DeviceLink& /*link*/) override {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto b : bytes) {
      if (partial_.empty()) partial_stamp_ns_ = arrival_ns;
      if (b == '\n') {
        handle_line();
        partial_.clear();
      } else if (partial_.size() < 256) {
        partial_.push_back(static_cast<char>(b));
      }
    }
  }

  drivers::SessionVerdict on_poll(drivers::DeviceLink& /*link*/, core::TimeNs now_ns) override {
    std::lock_guard<std::mutex> lock(mutex_);
    const core::TimeNs since =
        last_frame_ns_ == core::kNeverNs || last_frame_ns_ < open_ns_ ? open_ns_ : last_frame_ns_;
    if (options_.reopen_after_silence_ns > 0 && now_ns - since > options_.reopen_after_silence_ns) {
      return drivers::SessionVerdict::kReopen;
    }
    if (state_ == msg::DeviceState::kRunning && now_ns - since > options_.stale_after_ns) {
      state_ = msg::DeviceState::kStale;
    }
    return drivers::SessionVerdict::kContinue;
  }

  void on_close(core::TimeNs /*now_ns*/) override {
    std::lock_guard<std::mutex> lock(mutex_);
    ++closes_;
  }

  void fill_health(msg::DeviceHealth& health, core::TimeNs /*now_ns*/) const override {
    std::lock_guard<std::mutex> lock(mutex_);
    health.state = state_;
    health.frames_ok = frames_ok_;
    health.checksum_errors = checksum_errors_;
    health.framing_errors = framing_errors_;
    health.last_frame_ns = last_frame_ns_;
    health.set_detail(state_ == msg::DeviceState::kRunning ? "line frames arriving" : "waiting");
  }

  [[nodiscard]] std::vector<ReceivedLine> frames() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return frames_;
  }
  [[nodiscard]] std::vector<std::string> echoes() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return echoes_;
  }
  [[nodiscard]] std::size_t frame_count() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return frames_.size();
  }
  [[nodiscard]] std::vector<bool> write_results() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return write_results_;
  }
  [[nodiscard]] int opens() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return opens_;
  }
  [[nodiscard]] int closes() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return closes_;
  }

 private:
  void handle_line() {
    if (partial_.starts_with("ECHO:")) {
      echoes_.push_back(partial_.substr(5));
      return;
    }
    const std::size_t start = partial_.find('$');
    if (start == std::string::npos) {
      ++framing_errors_;
      return;
    }
    if (start > 0) ++framing_errors_;  // garbage before the frame: skipped
    const std::string_view frame = std::string_view(partial_).substr(start);
    const std::size_t star = frame.find('*');
    if (star == std::string_view::npos || frame.size() != star + 3) {
      ++framing_errors_;
      return;
    }
    if (checksummed(std::string(frame.substr(1, star - 1))) != std::string(frame) + "\n") {
      ++checksum_errors_;
      return;
    }
    ReceivedLine line;
    line.text = std::string(frame);
    line.stamp_ns = partial_stamp_ns_;
    const std::size_t comma = frame.rfind(',');
    line.emit_ns = std::stoll(std::string(frame.substr(comma + 1, star - comma - 1)));
    frames_.push_back(std::move(line));
    ++frames_ok_;
    last_frame_ns_ = partial_stamp_ns_;
    state_ = msg::DeviceState::kRunning;
  }

  const LineSessionOptions options_;
  mutable std::mutex mutex_;
  std::string partial_;
  core::TimeNs partial_stamp_ns_ = 0;
  core::TimeNs open_ns_ = 0;
  msg::DeviceState state_ = msg::DeviceState::kConfiguring;
  std::uint64_t frames_ok_ = 0;
  std::uint64_t checksum_errors_ = 0;
  std::uint64_t framing_errors_ = 0;
  core::TimeNs last_frame_ns_ = core::kNeverNs;
  std::vector<ReceivedLine> frames_;
  std::vector<std::string> echoes_;
  std::vector<bool> write_results_;
  int opens_ = 0;
  int closes_ = 0;
};

}  // namespace coxswain::test
