// SPDX-License-Identifier: Apache-2.0
#pragma once
// Bounded single-producer single-consumer queue of fixed-size slots, lock-free and wait-free on
// both sides. The producer claims a slot, fills it in place and publishes it; the consumer peeks
// the oldest slot, uses it in place and pops it, so nothing is copied twice and nothing is
// allocated after construction. A full queue makes try_claim() return nullptr: the producer
// drops and counts, it never waits.
// Thread-safety: exactly one producer thread (try_claim/publish) and one consumer thread
// (front/pop) at a time; the orders below publish the slot contents with the index.
#include <atomic>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <memory>

namespace coxswain::record {

template <class Slot>
class SpscRing {
 public:
  /// `capacity` is rounded up to a power of two (at least 2).
  explicit SpscRing(std::size_t capacity)
      : capacity_(std::bit_ceil(capacity < 2 ? std::size_t{2} : capacity)),
        mask_(capacity_ - 1),
        slots_(std::make_unique<Slot[]>(capacity_)) {}
  SpscRing(const SpscRing&) = delete;
  SpscRing& operator=(const SpscRing&) = delete;

  /// Producer: the next free slot, or nullptr when the queue is full.
  [[nodiscard]] Slot* try_claim() noexcept {
    const std::size_t head = head_.load(std::memory_order_relaxed);
    if (head - cached_tail_ >= capacity_) {
      cached_tail_ = tail_.load(std::memory_order_acquire);
      if (head - cached_tail_ >= capacity_) return nullptr;
    }
    return &slots_[head & mask_];
  }
  /// Producer: makes the slot returned by the last try_claim() visible to the consumer.
  void publish() noexcept {
    head_.store(head_.load(std::memory_order_relaxed) + 1, std::memory_order_release);
  }

  /// Consumer: the oldest published slot, or nullptr when empty.
  [[nodiscard]] Slot* front() noexcept {
    const std::size_t tail = tail_.load(std::memory_order_relaxed);
    if (tail == cached_head_) {
      cached_head_ = head_.load(std::memory_order_acquire);
      if (tail == cached_head_) return nullptr;
    }
    return &slots_[tail & mask_];
  }
  /// Consumer: releases the slot returned by front() back to the producer.
  void pop() noexcept {
    tail_.store(tail_.load(std::memory_order_relaxed) + 1, std::memory_order_release);
  }

  [[nodiscard]] std::size_t capacity() const { return capacity_; }
  /// Approximate number of queued slots (exact when both sides are idle).
  [[nodiscard]] std::size_t size() const {
    return head_.load(std::memory_order_acquire) - tail_.load(std::memory_order_acquire);
  }

 private:
  const std::size_t capacity_;
  const std::size_t mask_;
  std::unique_ptr<Slot[]> slots_;
  alignas(64) std::atomic<std::size_t> head_{0};  // written by the producer
  std::size_t cached_tail_ = 0;                   // producer's last view of tail_
  alignas(64) std::atomic<std::size_t> tail_{0};  // written by the consumer
  std::size_t cached_head_ = 0;                   // consumer's last view of head_
};

}  // namespace coxswain::record
