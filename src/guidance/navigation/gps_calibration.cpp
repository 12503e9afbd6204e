// SPDX-License-Identifier: Apache-2.0
#include "coxswain/guidance/gps_calibration.hpp"

#include <algorithm>
#include <cmath>

namespace coxswain::guidance {

std::optional<std::string> GpsCalibrationParams::validate() const {
  if (min_fixes < 1) return "gps calibration: min_fixes must be >= 1";
  if (window < min_fixes || window > GpsCalibration::kMaxFixes) {
    return "gps calibration: need min_fixes <= window <= 256";
  }
  if (!(max_spread_m > 0.0)) return "gps calibration: max_spread_m must be > 0";
  if (!(max_offset_m > 0.0)) return "gps calibration: max_offset_m must be > 0";
  return std::nullopt;
}

const char* to_string(CalibrationStatus s) {
  switch (s) {
    case CalibrationStatus::kOk:
      return "ok";
    case CalibrationStatus::kTooFewFixes:
      return "too few fixes";
    case CalibrationStatus::kSpreadTooLarge:
      return "fixes spread too wide";
    case CalibrationStatus::kOffsetTooLarge:
      return "offset too large";
  }
  return "unknown";
}

GpsCalibration::GpsCalibration(GpsCalibrationParams p, core::NavPoint known_start)
    : p_(p), start_(known_start), window_(std::clamp<std::size_t>(p.window, 1, kMaxFixes)) {}

void GpsCalibration::add(core::NavPoint measured) {
  if (!std::isfinite(measured.north_m) || !std::isfinite(measured.east_m)) return;
  fixes_[head_] = measured;
  head_ = (head_ + 1) % window_;
  count_ = std::min(count_ + 1, window_);
}

CalibrationResult GpsCalibration::result() const {
  CalibrationResult r;
  r.fix_count = count_;
  if (count_ == 0 || count_ < p_.min_fixes) return r;
  double sn = 0.0;
  double se = 0.0;
  for (std::size_t i = 0; i < count_; ++i) {
    sn += fixes_[i].north_m;
    se += fixes_[i].east_m;
  }
  const core::NavPoint mean{sn / static_cast<double>(count_), se / static_cast<double>(count_)};
  for (std::size_t i = 0; i < count_; ++i) {
    r.spread_m = std::max(r.spread_m, core::distance_m(fixes_[i], mean));
  }
  const GpsOffset off{mean.north_m - start_.north_m, mean.east_m - start_.east_m};
  if (r.spread_m > p_.max_spread_m) {
    r.status = CalibrationStatus::kSpreadTooLarge;
  } else if (std::hypot(off.north_m, off.east_m) > p_.max_offset_m) {
    r.status = CalibrationStatus::kOffsetTooLarge;
  } else {
    r.status = CalibrationStatus::kOk;
    r.offset = off;
  }
  return r;
}

}  // namespace coxswain::guidance
