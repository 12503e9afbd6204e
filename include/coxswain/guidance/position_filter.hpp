// SPDX-License-Identifier: Apache-2.0
#pragma once
// Position estimate between and across GNSS fixes: a complementary filter that dead-reckons with
// the receiver's velocity (which includes the drift of the current, unlike heading + log speed)
// and pulls the estimate toward each new fix by `gain`. A single fix carries ~0.4 m of white noise
// per axis; with gain 0.3 the estimate keeps about sqrt(g / (2 - g)) = 0.42 of it, and the
// extrapolation between 5 Hz fixes removes up to 0.2 s of lag (0.3 m at 1.5 m/s).
#include <optional>
#include <string>

#include "coxswain/core/frames.hpp"
#include "coxswain/core/time.hpp"

namespace coxswain::guidance {

struct PositionFilterParams {
  /// Weight of a new fix against the dead-reckoned estimate, in (0, 1]. 1 = the raw fixes, held
  /// between fixes (no dead reckoning): the documents' behaviour.
  double gain = 0.3;
  /// Fixes farther apart than this (an outage) restart the estimate at the new fix.
  double max_gap_s = 1.0;
  /// Dead reckoning past the last fix stops after this long (a stale receiver is a hold anyway).
  double max_predict_s = 0.5;
  [[nodiscard]] std::optional<std::string> validate() const;
};

/// Plain value, no allocation, deterministic; not thread-safe.
class PositionFilter {
 public:
  explicit PositionFilter(PositionFilterParams p = {}) : p_(p) {}

  /// A new fix (navigation frame) at `stamp_ns`, with the receiver's velocity when it has one
  /// (north, east m/s). Without a velocity the fix is taken as it is.
  void add_fix(core::NavPoint fix, core::TimeNs stamp_ns, std::optional<core::NavPoint> vel_mps);
  /// The estimate at `now_ns` (dead-reckoned from the last fix). Only meaningful after a fix.
  [[nodiscard]] core::NavPoint position_at(core::TimeNs now_ns) const;
  [[nodiscard]] bool has_estimate() const { return has_; }
  /// Displacement since the first fix from the receiver's velocity alone (trapezoids between
  /// fixes; an outage or a fix without velocity adds nothing). A boat waiting on the start point
  /// drifts with the current: the start calibration takes each fix back by this much.
  [[nodiscard]] core::NavPoint travelled_m() const { return travelled_; }
  void reset() {
    has_ = false;
    travelled_ = {};
  }

 private:
  PositionFilterParams p_;
  bool has_ = false;
  core::NavPoint est_;  // at stamp_ns_
  core::NavPoint vel_;  // m/s, north/east
  bool vel_valid_ = false;
  core::NavPoint travelled_;
  core::TimeNs stamp_ns_ = 0;
};

}  // namespace coxswain::guidance
