// SPDX-License-Identifier: Apache-2.0
#pragma once
// Messages per second over a sliding window, for DeviceHealth::rate_hz of device sessions.
#include <algorithm>
#include <array>
#include <cstddef>

#include "coxswain/core/time.hpp"

namespace coxswain::drivers {

/// A ring of the most recent `Capacity` arrival stamps. Value type, no allocation, not
/// thread-safe (a session's own state). Size the capacity for rate x window (100 Hz x 2 s fits
/// the default).
template <std::size_t Capacity = 256>
class RateWindow {
 public:
  void add(core::TimeNs t_ns) {
    stamps_[next_] = t_ns;
    next_ = (next_ + 1) % Capacity;
    count_ = std::min(count_ + 1, Capacity);
  }
  void clear() { count_ = 0; }

  /// (n - 1) / (newest - oldest) over the n stamps inside (now - window, now]; 0 below two.
  /// A silent device drops to 0 once its last stamps leave the window.
  [[nodiscard]] double rate_hz(core::TimeNs now_ns, core::TimeNs window_ns) const {
    std::size_t n = 0;
    core::TimeNs newest = 0;
    core::TimeNs oldest = 0;
    for (std::size_t k = 0; k < count_; ++k) {
      const core::TimeNs t = stamps_[(next_ + Capacity - 1 - k) % Capacity];
      if (t > now_ns || t <= now_ns - window_ns) break;  // newest first: the rest are older
      if (n == 0) newest = t;
      oldest = t;
      ++n;
    }
    if (n < 2 || newest <= oldest) return 0.0;
    return static_cast<double>(n - 1) / core::ns_to_sec(newest - oldest);
  }

 private:
  std::array<core::TimeNs, Capacity> stamps_{};
  std::size_t next_ = 0;
  std::size_t count_ = 0;
};

}  // namespace coxswain::drivers
