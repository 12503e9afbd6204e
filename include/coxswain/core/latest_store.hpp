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
    Padded env;
    env.env.value = value;
    env.env.stamp_ns = stamp_ns;
    env.env.count = seq / 2 + 1;
    const auto* src = reinterpret_cast<const unsigned char*>(&env);
    for (std::size_t i = 0; i < kWords; ++i) {
      std::uint64_t word = 0;
      std::memcpy(&word, src + i * 8, 8);
      words_[i].store(word, std::memory_order_release);
    }
    seq_.store(seq + 2, std::memory_order_release);
  }

  /// Copies the latest value into `out`. Lock-free; retries only while a write is in progress.
  void read(Sample<T>& out) const {
    Padded env;
    auto* dst = reinterpret_cast<unsigned char*>(&env);
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
      for (std::size_t i = 0; i < kWords; ++i) {
        const std::uint64_t word = words_[i].load(std::memory_order_acquire);
        std::memcpy(dst + i * 8, &word, 8);
      }
      if (seq_.load(std::memory_order_relaxed) == before) break;
      seqlock_pause(attempt);
    }
    out.value = env.env.value;
    out.stamp_ns = env.env.stamp_ns;
    out.sequence = env.env.count;
  }

  [[nodiscard]] Sample<T> read() const {
    Sample<T> s;
    read(s);
    return s;
  }

  /// Number of values published so far (cheap; no copy).
  [[nodiscard]] std::uint64_t sequence() const { return seq_.load(std::memory_order_acquire) / 2; }

 private:
  struct Envelope {
    T value{};
    TimeNs stamp_ns = kNeverNs;
    std::uint64_t count = 0;
  };
  // Padding bytes of Envelope are copied as they are; they are never read as values.
  static constexpr std::size_t kWords = (sizeof(Envelope) + 7) / 8;
  // Room for whole words so the word copy never runs past the envelope.
  struct Padded {
    Envelope env;
    unsigned char tail[kWords * 8 - sizeof(Envelope) + 1]{};
  };

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
};

}  // namespace coxswain::core
