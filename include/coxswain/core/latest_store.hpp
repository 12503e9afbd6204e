// SPDX-License-Identifier: Apache-2.0
#pragma once
// Lock-free latest-value store: one slot per topic, one writer per slot, any number of readers.
//
// Each slot is a sequence lock whose payload is held in atomic 64-bit words, a form of seqlock that
// is race-free in the C++ memory model (H.-J. Boehm, "Can seqlocks get along with programming
// language memory models?", MSPC 2012): the writer makes the sequence odd, stores the words with
// release order, then makes the sequence even again; a reader copies the words with acquire order
// between two reads of the sequence and retries if the sequence moved (a word from a newer write
// makes the odd sequence visible to the second read). No standalone fences, so ThreadSanitizer
// models it exactly; on x86 these orders cost nothing over relaxed ones. Readers never block the
// writer; a reader only retries while a write is in progress, so a torn value is never returned.
#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include "coxswain/core/time.hpp"
#include "coxswain/msg/actuator_command.hpp"
#include "coxswain/msg/arduino_status.hpp"
#include "coxswain/msg/camera_detections.hpp"
#include "coxswain/msg/device_health.hpp"
#include "coxswain/msg/gnss_fix.hpp"
#include "coxswain/msg/imu_sample.hpp"
#include "coxswain/msg/lidar_scan.hpp"
#include "coxswain/msg/operator_input.hpp"

namespace coxswain::core {

/// A value as read from a slot: the value, when it was stamped and how many times the slot has
/// been written (0 = never written, so `value` is default-constructed).
template <class T>
struct Sample {
  T value{};
  TimeNs stamp_ns = kNeverNs;
  std::uint64_t sequence = 0;

  [[nodiscard]] bool valid() const { return sequence != 0; }
  /// Age at `now_ns`; a never-written sample is infinitely old.
  [[nodiscard]] TimeNs age_ns(TimeNs now_ns) const {
    return valid() ? now_ns - stamp_ns : INT64_MAX;
  }
  [[nodiscard]] bool is_stale(TimeNs now_ns, TimeNs max_age_ns) const {
    return age_ns(now_ns) > max_age_ns;
  }
};

void seqlock_pause(unsigned attempt);

/// One topic. Thread-safety: `publish` from exactly one thread; `read` from any number.
template <class T>
class LatestSlot {
  static_assert(std::is_trivially_copyable_v<T>, "slots hold plain data only");

 public:
  LatestSlot() {
    for (auto& w : words_) w.store(0, std::memory_order_relaxed);
  }
  LatestSlot(const LatestSlot&) = delete;
  LatestSlot& operator=(const LatestSlot&) = delete;

  /// Stores a new value. Single writer only. Wait-free.
  void publish(const T& value, TimeNs stamp_ns) {
    const std::uint64_t seq = seq_.load(std::memory_order_relaxed);
    seq_.store(seq + 1, std::memory_order_relaxed);
    // The value's words straight from `value`, then the stamp and count: no envelope built (and
    // zeroed) first, which for a 64 KiB scan cost more than the copy.
    const auto* src = reinterpret_cast<const unsigned char*>(&value);
    for (std::size_t i = 0; i < kValueWords; ++i) {
      std::uint64_t word = 0;
      std::memcpy(&word, src + i * 8, 8);
      words_[i].store(word, std::memory_order_release);
    }
    if constexpr (kValueTail != 0) {
      std::uint64_t word = 0;
      std::memcpy(&word, src + kValueWords * 8, kValueTail);
      words_[kValueWords].store(word, std::memory_order_release);
    }
    words_[kStampWord].store(static_cast<std::uint64_t>(stamp_ns), std::memory_order_release);
    words_[kStampWord + 1].store(seq / 2 + 1, std::memory_order_release);
    seq_.store(seq + 2, std::memory_order_release);
  }

  /// Copies the latest value into `out`. Lock-free; retries only while a write is in progress.
  void read(Sample<T>& out) const {
    for (unsigned attempt = 0;; ++attempt) {
      const std::uint64_t before = seq_.load(std::memory_order_acquire);
      if (before == 0) {
        out = Sample<T>{};
        return;
      }
      if ((before & 1U) != 0) {
        seqlock_pause(attempt);
        continue;
      }
      // Into `out` itself (a copy torn by a concurrent write is overwritten by the retry).
      auto* dst = reinterpret_cast<unsigned char*>(&out.value);
      for (std::size_t i = 0; i < kValueWords; ++i) {
        const std::uint64_t word = words_[i].load(std::memory_order_acquire);
        std::memcpy(dst + i * 8, &word, 8);
      }
      if constexpr (kValueTail != 0) {
        const std::uint64_t word = words_[kValueWords].load(std::memory_order_acquire);
        std::memcpy(dst + kValueWords * 8, &word, kValueTail);
      }
      const std::uint64_t stamp = words_[kStampWord].load(std::memory_order_acquire);
      const std::uint64_t count = words_[kStampWord + 1].load(std::memory_order_acquire);
      if (seq_.load(std::memory_order_relaxed) == before) {
        out.stamp_ns = static_cast<TimeNs>(stamp);
        out.sequence = count;
        return;
      }
      seqlock_pause(attempt);
    }
  }
  /// As read(), but leaves `out` alone when it already holds the latest value, i.e. when its
  /// sequence is the slot's: for a caller that refreshes the same Sample from this slot tick
  /// after tick and does not change it in between.
  void refresh(Sample<T>& out) const {
    const std::uint64_t now = seq_.load(std::memory_order_acquire);
    if (now != 0 && (now & 1U) == 0 && out.sequence == now / 2) return;
    read(out);
  }
  [[nodiscard]] Sample<T> read() const {
    Sample<T> s;
    read(s);
    return s;
  }

  /// Number of values published so far (cheap; no copy).
  [[nodiscard]] std::uint64_t sequence() const { return seq_.load(std::memory_order_acquire) / 2; }

 private:
  // The value's bytes in whole words (the last one partly used), then the stamp and the count.
  static constexpr std::size_t kValueWords = sizeof(T) / 8;
  static constexpr std::size_t kValueTail = sizeof(T) % 8;
  static constexpr std::size_t kStampWord = kValueWords + (kValueTail != 0 ? 1 : 0);
  static constexpr std::size_t kWords = kStampWord + 2;
  alignas(64) std::atomic<std::uint64_t> seq_{0};
  alignas(64) std::array<std::atomic<std::uint64_t>, kWords> words_;
};

/// Everything the tick reads, copied once per tick. Large (a lidar scan is about 64 KiB): keep
/// one instance and refill it with LatestStore::snapshot(out), which does not allocate.
struct Snapshot {
  Sample<msg::LidarScan> lidar;
  Sample<msg::ImuSample> imu;
  Sample<msg::GnssFix> gnss;
  Sample<msg::CameraDetections> camera;
  Sample<msg::ArduinoStatus> arduino;
  Sample<msg::OperatorInput> operator_input;
  std::array<Sample<msg::DeviceHealth>, msg::kDeviceCount> health;
};

/// The set of slots the daemon shares between its drivers and its tick. Each member has exactly
/// one writer: its driver (health[i] by driver i; operator_input by the control interface).
class LatestStore {
 public:
  LatestSlot<msg::LidarScan> lidar;
  LatestSlot<msg::ImuSample> imu;
  LatestSlot<msg::GnssFix> gnss;
  LatestSlot<msg::CameraDetections> camera;
  LatestSlot<msg::ArduinoStatus> arduino;
  LatestSlot<msg::OperatorInput> operator_input;
  std::array<LatestSlot<msg::DeviceHealth>, msg::kDeviceCount> health;
  /// The tick's output for the Arduino driver (writer: the tick thread). Not in the Snapshot.
  LatestSlot<msg::ActuatorCommand> command;

  [[nodiscard]] LatestSlot<msg::DeviceHealth>& health_of(msg::DeviceId id) {
    return health[static_cast<std::size_t>(id)];
  }

  /// Reads every slot into `out`. Each slot is self-consistent; slots are read one after another.
  void snapshot(Snapshot& out) const;
  /// As snapshot(), but a slot `out` already holds at its latest value is not copied again (see
  /// LatestSlot::refresh): for a tick that refreshes one Snapshot from this store and never
  /// changes it. The same Snapshot as snapshot() would give.
  void refresh(Snapshot& out) const;
};

}  // namespace coxswain::core
