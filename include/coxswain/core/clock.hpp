// SPDX-License-Identifier: Apache-2.0
#pragma once
// Injectable clocks. Only drivers and the app hold a clock; the core receives `now` as an argument.
#include <atomic>

#include "coxswain/core/time.hpp"

namespace coxswain::core {

/// A source of steady time. Implementations are thread-safe.
class Clock {
 public:
  virtual ~Clock() = default;
  [[nodiscard]] virtual TimeNs now_ns() const = 0;
};

/// std::chrono::steady_clock, the daemon's clock.
class SteadyClock final : public Clock {
 public:
  [[nodiscard]] TimeNs now_ns() const override;
};

/// Virtual time moved by its owner: the simulator in lockstep and replay both use it.
/// Thread-safe; time never goes backwards (set_ns to an earlier time is ignored).
class ManualClock final : public Clock {
 public:
  explicit ManualClock(TimeNs start_ns = 0) : now_ns_(start_ns) {}
  [[nodiscard]] TimeNs now_ns() const override { return now_ns_.load(std::memory_order_acquire); }
  void advance_ns(TimeNs delta_ns);
  void set_ns(TimeNs t_ns);

 private:
  std::atomic<TimeNs> now_ns_;
};

}  // namespace coxswain::core
