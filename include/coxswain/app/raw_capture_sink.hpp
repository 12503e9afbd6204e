// SPDX-License-Identifier: Apache-2.0
#pragma once
// Capture mode (`coxswain run --capture-dir DIR`): every byte each serial device sends is written
// to DIR/<device>.raw (lidar.raw, imu.raw, gnss.raw, arduino.raw), the files `coxswain decode`
// reads.
#include <array>
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <mutex>
#include <thread>

#include "coxswain/core/time.hpp"
#include "coxswain/drivers/device_session.hpp"

namespace coxswain::app {

/// A RawByteSink that never blocks its callers: each device has a lock-free single-producer /
/// single-consumer byte ring, filled by on_raw() on the device's thread and emptied into the
/// device's file by the sink's own writer thread every `flush_period_ns`. A ring too full for a
/// chunk drops the whole chunk and counts it (the file then misses those bytes; the counts say
/// how many). Only bytes from the device are captured (bytes we send are not).
///
/// Thread-safety: on_raw() from at most one thread per device (each transport is the single
/// producer of its device's ring); counters() from any thread; stop() and the destructor from
/// the owner, after the producers have stopped (the transports hold a pointer to the sink).
class RawCaptureSink final : public drivers::RawByteSink {
 public:
  static constexpr std::size_t kDefaultRingBytes = std::size_t{1} << 20;

  struct DeviceCounters {
    std::uint64_t bytes_written = 0;  // in the file
    std::uint64_t bytes_dropped = 0;  // ring full, file unwritable, or after stop()
  };

  /// Creates `dir` if needed (throws std::filesystem::filesystem_error when it cannot) and
  /// starts the writer thread. Files are created at the first byte of each device.
  explicit RawCaptureSink(std::filesystem::path dir, std::size_t ring_bytes = kDefaultRingBytes,
                          core::TimeNs flush_period_ns = 20 * core::kNsPerMs);
  ~RawCaptureSink() override;
  RawCaptureSink(const RawCaptureSink&) = delete;
  RawCaptureSink& operator=(const RawCaptureSink&) = delete;

  void on_raw(msg::DeviceId device, drivers::RawDirection direction, core::TimeNs stamp_ns,
              std::span<const std::uint8_t> bytes) noexcept override;

  /// Writes out everything queued, closes the files and joins the writer. Idempotent.
  void stop();

  [[nodiscard]] DeviceCounters counters(msg::DeviceId device) const;
  [[nodiscard]] static std::filesystem::path file_for(const std::filesystem::path& dir,
                                                      msg::DeviceId device);

 private:
  struct Ring {
    std::unique_ptr<std::uint8_t[]> data;
    // Monotonic byte counts: head written by the producer, tail by the writer thread.
    alignas(64) std::atomic<std::uint64_t> head{0};
    alignas(64) std::atomic<std::uint64_t> tail{0};
    std::atomic<std::uint64_t> written{0};
    std::atomic<std::uint64_t> dropped{0};
    std::FILE* file = nullptr;  // writer thread only
    bool file_failed = false;   // writer thread only
  };

  void run();
  void drain(msg::DeviceId device, Ring& ring);

  const std::filesystem::path dir_;
  const std::size_t capacity_;
  const core::TimeNs flush_period_ns_;
  std::array<Ring, msg::kDeviceCount> rings_;
  std::atomic<bool> accepting_{true};
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  std::thread thread_;
};

}  // namespace coxswain::app
