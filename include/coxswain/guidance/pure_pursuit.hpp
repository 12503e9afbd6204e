// SPDX-License-Identifier: Apache-2.0
#pragma once
// Pure-pursuit path tracking (the capstone report; docs/missions.md): aim at the point of the path
// one look-ahead distance away; the arc through it has curvature k = 2 sin(alpha) / l_d, alpha
// being the angle between the heading and that point. Short look-ahead oscillates, long cuts
// corners.
#include <cstddef>
#include <optional>
#include <span>
#include <string>

#include "coxswain/core/frames.hpp"

namespace coxswain::guidance {

struct PurePursuitParams {
  double lookahead_m = 2.5;      // l_d
  double arrive_radius_m = 1.0;  // within this of the last point the path is done
  /// Empty when valid, else the first problem found.
  [[nodiscard]] std::optional<std::string> validate() const;
};

struct PursuitCommand {
  bool valid = false;            // false for an empty path
  bool at_end = false;           // within arrive_radius_m of the last point
  core::NavPoint target{};       // the look-ahead point
  double heading_deg = 0.0;      // desired heading psi_d (navigation frame) toward the target
  double alpha_deg = 0.0;        // turn from the current heading to the target, + starboard
  double curvature_per_m = 0.0;  // 2 sin(alpha) / distance to target; + turns to starboard
  std::size_t segment = 0;       // index of the path segment the boat is abeam of
};

/// Tracks a polyline in the navigation frame. Remembers how far along the path the boat has come
/// (it never searches backwards, so a path that passes near itself is followed in order); call
/// `reset` for a new path. Not thread-safe; no allocation.
class PurePursuit {
 public:
  explicit PurePursuit(const PurePursuitParams& params) : params_(params) {}

  [[nodiscard]] PursuitCommand update(std::span<const core::NavPoint> path,
                                      const core::NavPose& pose);
  void reset() { progress_ = 0; }
  [[nodiscard]] const PurePursuitParams& params() const { return params_; }

 private:
  PurePursuitParams params_;
  std::size_t progress_ = 0;
};

}  // namespace coxswain::guidance
