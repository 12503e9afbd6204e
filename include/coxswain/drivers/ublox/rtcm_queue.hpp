// SPDX-License-Identifier: Apache-2.0
#pragma once
// Lock-free single-producer/single-consumer queue of whole RTCM 3 frames, the hand-over from the
// correction reader's thread (RtcmSource) to the GNSS device thread (UbloxSession::on_poll).
#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>

namespace coxswain::drivers::ublox {

/// Largest RTCM 3 frame: 3-byte header + 1023-byte payload + 3-byte CRC.
inline constexpr std::size_t kMaxRtcm3FrameBytes = 1029;

/// Fixed-capacity ring of RTCM 3 frames. Thread-safety: push() from exactly one thread, pop()
/// from exactly one other thread; both wait-free, no allocation. A full queue drops the new
/// frame (corrections are only useful fresh; the producer counts the drop).
template <std::size_t Capacity = 64>
class RtcmFrameQueue {
  static_assert(Capacity >= 2 && (Capacity & (Capacity - 1)) == 0, "power of two");

 public:
  struct Slot {
    std::array<std::uint8_t, kMaxRtcm3FrameBytes> bytes{};
    std::size_t size = 0;
    [[nodiscard]] std::span<const std::uint8_t> view() const { return {bytes.data(), size}; }
  };

  /// Producer: copies `frame` in. False when full or the frame is too long.
  bool push(std::span<const std::uint8_t> frame) {
    if (frame.size() > kMaxRtcm3FrameBytes) return false;
    const std::size_t head = head_.load(std::memory_order_relaxed);
    if (head - tail_.load(std::memory_order_acquire) >= Capacity) return false;
    Slot& s = slots_[head & (Capacity - 1)];
    std::memcpy(s.bytes.data(), frame.data(), frame.size());
    s.size = frame.size();
    head_.store(head + 1, std::memory_order_release);
    return true;
  }

  /// Consumer: the oldest frame, or nullptr when empty. The slot stays valid until release().
  [[nodiscard]] const Slot* front() const {
    const std::size_t tail = tail_.load(std::memory_order_relaxed);
    if (tail == head_.load(std::memory_order_acquire)) return nullptr;
    return &slots_[tail & (Capacity - 1)];
  }
  /// Consumer: drops the frame returned by front().
  void release() {
    tail_.store(tail_.load(std::memory_order_relaxed) + 1, std::memory_order_release);
  }

  [[nodiscard]] static constexpr std::size_t capacity() { return Capacity; }

 private:
  std::array<Slot, Capacity> slots_{};
  alignas(64) std::atomic<std::size_t> head_{0};
  alignas(64) std::atomic<std::size_t> tail_{0};
};

/// The queue type the session and the source share.
using RtcmQueue = RtcmFrameQueue<64>;

}  // namespace coxswain::drivers::ublox
