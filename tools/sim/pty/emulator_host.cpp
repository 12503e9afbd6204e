// SPDX-License-Identifier: Apache-2.0
#include "sim/pty/emulator_host.hpp"

#include <algorithm>
#include <chrono>
#include <utility>

namespace coxswain::sim::pty {
namespace {

core::TimeNs steady_now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

}  // namespace

EmulatorHost::EmulatorHost(devices::DeviceEmulator& device, Options options)
    : device_(device),
      options_(std::move(options)),
      pty_(std::make_unique<PseudoTerminal>(options_.link_path)),
      rng_(options_.seed),
      read_buf_(4096) {
  pending_.reserve(options_.max_pending_bytes);
  thread_ = std::thread([this] { run(); });
}

EmulatorHost::~EmulatorHost() {
  stop();
  pty_.reset();
}

void EmulatorHost::stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

std::string EmulatorHost::device_path() const {
  if (!options_.link_path.empty()) return options_.link_path.string();
  return slave_name();
}

std::string EmulatorHost::slave_name() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return pty_ ? pty_->slave_name() : std::string();
}

void EmulatorHost::unplug() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!pty_) return;
  pty_.reset();  // removes the link and closes the master: the host's reads fail
  pending_.clear();
  ++counters_.unplugs;
}

void EmulatorHost::replug() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (pty_ || stopping_) return;
  pty_ = std::make_unique<PseudoTerminal>(options_.link_path);
  ++counters_.replugs;
}

bool EmulatorHost::plugged() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return pty_ != nullptr;
}

void EmulatorHost::set_silent(bool silent) {
  std::lock_guard<std::mutex> lock(mutex_);
  silent_ = silent;
  if (silent) pending_.clear();  // what sat in the device's FIFO is not sent either
}

void EmulatorHost::set_garbage(double probability, std::size_t max_burst_bytes) {
  std::lock_guard<std::mutex> lock(mutex_);
  garbage_probability_ = std::clamp(probability, 0.0, 1.0);
  garbage_max_bytes_ = std::max<std::size_t>(1, max_burst_bytes);
}

void EmulatorHost::set_corruption(double bit_flip_probability) {
  std::lock_guard<std::mutex> lock(mutex_);
  flip_probability_ = std::clamp(bit_flip_probability, 0.0, 1.0);
}

HostCounters EmulatorHost::counters() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return counters_;
}

void EmulatorHost::run() {
  std::unique_lock<std::mutex> lock(mutex_);
  auto deadline = std::chrono::steady_clock::now();
  while (!stopping_) {
    service(steady_now_ns());
    deadline += std::chrono::nanoseconds(options_.tick_ns);
    const auto now = std::chrono::steady_clock::now();
    // After a long stall (debugger, loaded CI) do not fire a burst of catch-up ticks.
    if (deadline < now) deadline = now;
    wake_.wait_until(lock, deadline, [this] { return stopping_; });
  }
}

void EmulatorHost::service(core::TimeNs now_ns) {
  // Host -> device.
  if (pty_) {
    for (;;) {
      const std::size_t n = pty_->read(read_buf_);
      if (n == 0) break;
      counters_.bytes_from_host += n;
      device_.receive(std::span<const std::uint8_t>(read_buf_.data(), n), now_ns);
    }
  }
  // Device -> host, with faults.
  const std::span<const std::uint8_t> out = device_.poll(now_ns);
  counters_.device_bytes += out.size();
  if (!out.empty()) {
    if (!pty_) {
      counters_.unplugged_bytes += out.size();
    } else if (silent_) {
      counters_.silenced_bytes += out.size();
    } else {
      if (rng_.chance(garbage_probability_)) {
        const std::size_t n = 1 + static_cast<std::size_t>(rng_.below(garbage_max_bytes_));
        scratch_.resize(n);
        for (auto& b : scratch_) b = static_cast<std::uint8_t>(rng_.next_u64() & 0xFFU);
        ++counters_.garbage_bursts;
        counters_.garbage_bytes += n;
        enqueue(scratch_);
      }
      scratch_.assign(out.begin(), out.end());
      if (flip_probability_ > 0.0) {
        for (auto& b : scratch_) {
          if (rng_.chance(flip_probability_)) {
            b = static_cast<std::uint8_t>(b ^ (1U << rng_.below(8)));
            ++counters_.bits_flipped;
          }
        }
      }
      enqueue(scratch_);
    }
  }
  flush_pending();
}

void EmulatorHost::enqueue(std::span<const std::uint8_t> bytes) {
  pending_.insert(pending_.end(), bytes.begin(), bytes.end());
  if (pending_.size() > options_.max_pending_bytes) {
    const std::size_t excess = pending_.size() - options_.max_pending_bytes;
    pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(excess));
    counters_.overflow_bytes += excess;
  }
}

void EmulatorHost::flush_pending() {
  if (!pty_ || pending_.empty()) return;
  const std::size_t n = pty_->write(pending_);
  counters_.bytes_to_host += n;
  pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(n));
}

}  // namespace coxswain::sim::pty
