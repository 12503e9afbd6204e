// SPDX-License-Identifier: Apache-2.0
#pragma once
// The track drawn on the map: the boat's positions, a point whenever it has moved `spacing_m`
// from the last one. When kMaxPoints fill, every other point goes and the spacing doubles, so
// a run of any length fits and its start stays. Allocates once, in the constructor.
#include <cstddef>
#include <span>
#include <vector>

#include "coxswain/record/tick_record.hpp"

namespace coxswain::record {

class TrackLine {
 public:
  static constexpr std::size_t kMaxPoints = 512;

  explicit TrackLine(double spacing_m = 1.0);
  void add(VizPoint p);
  [[nodiscard]] std::span<const VizPoint> points() const { return points_; }
  [[nodiscard]] double spacing_m() const { return spacing_m_; }

 private:
  std::vector<VizPoint> points_;
  double spacing_m_;
};

}  // namespace coxswain::record
