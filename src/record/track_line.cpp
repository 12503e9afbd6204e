// SPDX-License-Identifier: Apache-2.0
#include "coxswain/record/track_line.hpp"

#include <cmath>

namespace coxswain::record {

TrackLine::TrackLine(double spacing_m)
    // A spacing that is not positive would never grow: a millimetre at least.
    : spacing_m_(std::isfinite(spacing_m) && spacing_m > 1e-3 ? spacing_m : 1e-3) {
  points_.reserve(kMaxPoints);
}

void TrackLine::add(VizPoint p) {
  if (!std::isfinite(p.north_m) || !std::isfinite(p.east_m)) return;
  if (!points_.empty()) {
    const VizPoint& last = points_.back();
    if (std::hypot(p.north_m - last.north_m, p.east_m - last.east_m) < spacing_m_) return;
  }
  if (points_.size() >= kMaxPoints) {
    std::size_t kept = 0;
    for (std::size_t i = 0; i < points_.size(); i += 2) points_[kept++] = points_[i];
    points_.resize(kept);
    spacing_m_ *= 2.0;
  }
  points_.push_back(p);
}

}  // namespace coxswain::record
