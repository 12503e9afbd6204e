// SPDX-License-Identifier: Apache-2.0
#include "coxswain/guidance/position_filter.hpp"

#include <algorithm>
#include <cmath>

namespace coxswain::guidance {

std::optional<std::string> PositionFilterParams::validate() const {
  if (!(gain > 0.0 && gain <= 1.0)) return "navigation.position_gain must be in (0, 1]";
  if (!(max_gap_s > 0.0) || !std::isfinite(max_gap_s)) return "position filter max_gap_s > 0";
  if (!(max_predict_s >= 0.0) || !std::isfinite(max_predict_s)) {
    return "position filter max_predict_s >= 0";
  }
  return std::nullopt;
}

void PositionFilter::add_fix(core::NavPoint fix, core::TimeNs stamp_ns,
                             std::optional<core::NavPoint> vel_mps) {
  const double gap_s = has_ ? core::ns_to_sec(stamp_ns - stamp_ns_) : 0.0;
  const bool raw = p_.gain >= 1.0 || !vel_mps;
  if (has_ && vel_valid_ && vel_mps && gap_s > 0.0 && gap_s <= p_.max_gap_s) {
    travelled_.north_m += 0.5 * (vel_.north_m + vel_mps->north_m) * gap_s;
    travelled_.east_m += 0.5 * (vel_.east_m + vel_mps->east_m) * gap_s;
  }
  if (!has_ || raw || gap_s < 0.0 || gap_s > p_.max_gap_s) {
    est_ = fix;
  } else {
    // Dead-reckon the estimate to the fix's time with the last velocity, then blend.
    const core::NavPoint pred{est_.north_m + vel_.north_m * gap_s,
                              est_.east_m + vel_.east_m * gap_s};
    est_ = {pred.north_m + p_.gain * (fix.north_m - pred.north_m),
            pred.east_m + p_.gain * (fix.east_m - pred.east_m)};
  }
  vel_ = vel_mps.value_or(core::NavPoint{});
  vel_valid_ = vel_mps.has_value();
  stamp_ns_ = stamp_ns;
  has_ = true;
}

core::NavPoint PositionFilter::position_at(core::TimeNs now_ns) const {
  if (p_.gain >= 1.0 || !vel_valid_) return est_;
  const double dt = std::clamp(core::ns_to_sec(now_ns - stamp_ns_), 0.0, p_.max_predict_s);
  return {est_.north_m + vel_.north_m * dt, est_.east_m + vel_.east_m * dt};
}

}  // namespace coxswain::guidance
