// SPDX-License-Identifier: Apache-2.0
#include "coxswain/app/raw_capture_sink.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <string>

namespace coxswain::app {

RawCaptureSink::RawCaptureSink(std::filesystem::path dir, std::size_t ring_bytes,
                               core::TimeNs flush_period_ns)
    : dir_(std::move(dir)),
      capacity_(std::max<std::size_t>(ring_bytes, 1)),
      flush_period_ns_(flush_period_ns) {
  std::filesystem::create_directories(dir_);
  for (Ring& r : rings_) r.data = std::make_unique<std::uint8_t[]>(capacity_);
  thread_ = std::thread([this] { run(); });
}

RawCaptureSink::~RawCaptureSink() { stop(); }

std::filesystem::path RawCaptureSink::file_for(const std::filesystem::path& dir,
                                               msg::DeviceId device) {
  return dir / (std::string(msg::device_name(device)) + ".raw");
}

void RawCaptureSink::on_raw(msg::DeviceId device, drivers::RawDirection direction,
                            core::TimeNs /*stamp_ns*/,
                            std::span<const std::uint8_t> bytes) noexcept {
  if (direction != drivers::RawDirection::kFromDevice || bytes.empty()) return;
  const auto index = static_cast<std::size_t>(device);
  if (index >= rings_.size()) return;
  Ring& r = rings_[index];
  if (!accepting_.load(std::memory_order_acquire)) {
    r.dropped.fetch_add(bytes.size(), std::memory_order_relaxed);
    return;
  }
  const std::uint64_t head = r.head.load(std::memory_order_relaxed);
  const std::uint64_t tail = r.tail.load(std::memory_order_acquire);
  if (capacity_ - (head - tail) < bytes.size()) {
    r.dropped.fetch_add(bytes.size(), std::memory_order_relaxed);
    return;
  }
  const std::size_t at = static_cast<std::size_t>(head % capacity_);
  const std::size_t first = std::min(bytes.size(), capacity_ - at);
  std::memcpy(r.data.get() + at, bytes.data(), first);
  std::memcpy(r.data.get(), bytes.data() + first, bytes.size() - first);
  r.head.store(head + bytes.size(), std::memory_order_release);
}

void RawCaptureSink::drain(msg::DeviceId device, Ring& r) {
  const std::uint64_t tail = r.tail.load(std::memory_order_relaxed);
  const std::uint64_t head = r.head.load(std::memory_order_acquire);
  if (head == tail) return;
  const auto n = static_cast<std::size_t>(head - tail);
  if (r.file == nullptr && !r.file_failed) {
    const std::filesystem::path path = file_for(dir_, device);
    r.file = std::fopen(path.c_str(), "wb");
    if (r.file == nullptr) {
      r.file_failed = true;
      spdlog::error("capture: cannot write {}: {}", path.string(), std::strerror(errno));
    }
  }
  if (r.file != nullptr) {
    const std::size_t at = static_cast<std::size_t>(tail % capacity_);
    const std::size_t first = std::min(n, capacity_ - at);
    std::size_t done = std::fwrite(r.data.get() + at, 1, first, r.file);
    if (done == first && n > first) done += std::fwrite(r.data.get(), 1, n - first, r.file);
    r.written.fetch_add(done, std::memory_order_relaxed);
    r.dropped.fetch_add(n - done, std::memory_order_relaxed);
  } else {
    r.dropped.fetch_add(n, std::memory_order_relaxed);
  }
  r.tail.store(head, std::memory_order_release);
}

void RawCaptureSink::run() {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    const bool stopping =
        wake_.wait_for(lock, std::chrono::nanoseconds(flush_period_ns_), [this] { return stop_; });
    lock.unlock();
    for (std::size_t i = 0; i < rings_.size(); ++i) {
      Ring& r = rings_[i];
      drain(static_cast<msg::DeviceId>(i), r);
      if (r.file != nullptr) std::fflush(r.file);
    }
    lock.lock();
    if (stopping) return;
  }
}

void RawCaptureSink::stop() {
  if (!thread_.joinable()) return;
  accepting_.store(false, std::memory_order_release);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  thread_.join();
  for (std::size_t i = 0; i < rings_.size(); ++i) {
    Ring& r = rings_[i];
    drain(static_cast<msg::DeviceId>(i), r);  // a producer that raced with stop()
    if (r.file != nullptr) {
      std::fclose(r.file);
      r.file = nullptr;
    }
    const DeviceCounters c = counters(static_cast<msg::DeviceId>(i));
    if (c.bytes_written > 0 || c.bytes_dropped > 0) {
      spdlog::info("capture: {} {} bytes written, {} dropped",
                   file_for(dir_, static_cast<msg::DeviceId>(i)).string(), c.bytes_written,
                   c.bytes_dropped);
    }
  }
}

RawCaptureSink::DeviceCounters RawCaptureSink::counters(msg::DeviceId device) const {
  const Ring& r = rings_[static_cast<std::size_t>(device)];
  return {r.written.load(std::memory_order_relaxed), r.dropped.load(std::memory_order_relaxed)};
}

}  // namespace coxswain::app
