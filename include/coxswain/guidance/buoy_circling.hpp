// SPDX-License-Identifier: Apache-2.0
#pragma once
// Circling a buoy once (2026 plan, course 2, docs/missions.md): keep the camera-tracked buoy
// at a set body bearing (the camera looks to port, -90 deg) and, when the lidar gives its range,
// at a set distance; "line tracing" around it. Completion is the accumulated turn, integrated from
// wrap-safe heading differences, reaching 360 deg -- not the heading crossing 0 twice, which a
// noisy compass near north does many times. Only the turn made with the buoy observed counts.
#include <optional>
#include <string>

namespace coxswain::guidance {

struct BuoyCirclingParams {
  double target_bearing_deg = -90.0;      // body bearing to hold the buoy at (- = port)
  double target_distance_m = 3.0;         // distance to hold when a range is known
  double bearing_gain = 1.0;              // desired turn per degree of bearing error
  double distance_gain_deg_per_m = 10.0;  // turn toward/away from the buoy per metre of error
  double max_distance_correction_deg = 30.0;
  double max_turn_deg = 60.0;          // clamp of |desired - heading| per step
  double search_turn_deg = 20.0;       // buoy not seen: keep turning this much to its side
  double complete_turn_deg = 360.0;    // accumulated turn that finishes the circle
  double max_heading_step_deg = 60.0;  // a bigger jump between samples is a glitch, not a turn
  // Only turns made with the buoy in sight count: a boat turning blind (searching, or circling
  // the wrong thing) has not gone round the buoy. Off (the default, the documents' way): every
  // turn counts. On, a boat whose camera loses the buoy for part of the circle undercounts.
  bool count_only_seen = false;

  [[nodiscard]] std::optional<std::string> validate() const;
};

/// This frame's buoy, body frame. Empty bearing = not seen.
struct BuoyObservation {
  std::optional<double> bearing_deg;
  std::optional<double> range_m;  // lidar range to the buoy when associated
};

/// Headings TRUE, navigation frame.
struct BuoyCirclingOutput {
  double desired_heading_deg = 0.0;
  double turned_deg = 0.0;    // accumulated signed heading change (+ = clockwise)
  double progress_deg = 0.0;  // turn in the circling direction (to the buoy's side)
  double bearing_error_deg = 0.0;
  bool buoy_seen = false;
  bool done = false;
};

/// Plain value, no allocation, not thread-safe.
class BuoyCircling {
 public:
  explicit BuoyCircling(BuoyCirclingParams p = {}) : p_(p) {}
  BuoyCirclingOutput update(double heading_deg, const BuoyObservation& obs);
  void reset();
  [[nodiscard]] double progress_deg() const;

 private:
  BuoyCirclingParams p_;
  double turned_deg_ = 0.0;
  double last_heading_deg_ = 0.0;
  bool has_heading_ = false;
  bool done_ = false;
};

}  // namespace coxswain::guidance
