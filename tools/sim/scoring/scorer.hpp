// SPDX-License-Identifier: Apache-2.0
#pragma once
// Judging a run against the contest rules. The boat is its hull outline (config hull length,
// beam, bow overhang: a pentagon with a pointed bow), never a point:
// - collisions: the outline touching a wall, buoy or dock (within `touch_m`: the simulator's
//   collision response leaves a hull exactly touching what it hit); counted once per contact (a
//   contact starts at touch and ends only after the hull is `release_m` clear again, so scraping
//   along a wall is one collision);
// - pinned: a hull that stays in one contact without getting `pinned_radius_m` away from where
//   it was for `pinned_s` is stuck; the run ends there, not completed (a failure);
// - waypoints: the 2022 rule, at least half the hull's area inside the waypoint's circle
//   (area sampled on a fixed grid); hopping and 2026 waypoints count only in order;
// - gates: the centre of gravity crossing the gate segment left -> right in the course direction;
// - docks: at least half the hull's area inside the slip;
// - time limits per course region; penalties and bonuses of the year's rules (see Rules);
// - 2026: the angle the centre of gravity sweeps around the purple buoy (a full turn = circled).
// Not thread-safe; feed one run's truth states in time order.
#include <array>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "coxswain/config/config.hpp"
#include "coxswain/msg/actuator_command.hpp"
#include "sim/dynamics/boat_model.hpp"
#include "sim/world/world.hpp"

namespace coxswain::sim::scoring {

/// Which rule book judges the run (from the course type).
enum class Rules : std::uint8_t { k2022Hopping, k2022Obstacle, k2022Docking, k2026 };
Rules rules_for(world::CourseKind kind);
std::string_view rules_name(Rules rules);

enum class ObstacleKind : std::uint8_t { kWall, kBuoy, kDock };

/// The hull outline in the body frame: bow tip, starboard shoulder, starboard stern corner, port
/// stern corner, port shoulder (the shoulders a quarter length aft of the bow tip).
std::array<core::BodyPoint, 5> hull_outline_body(const config::HullConfig& hull);
/// The outline placed at `pose` (pose of the body origin).
std::array<core::NavPoint, 5> hull_outline(const config::HullConfig& hull,
                                           const core::NavPose& pose);

struct Contact {
  double t_s = 0.0;
  core::NavPoint at;  // the boat's centre of gravity at first touch
  std::string obstacle;
  ObstacleKind kind = ObstacleKind::kWall;
  std::size_t course = 0;  // index of the course region the boat was in
  bool penalised = true;
  // How it was touched: the heading, the speed along it (negative astern) and the bearing off
  // the bow of the obstacle's point nearest the centre of gravity (0 ahead, +-180 astern).
  double heading_deg = 0.0;
  double surge_mps = 0.0;
  double bearing_body_deg = 0.0;
};

struct Passage {
  std::string name;
  double t_s = 0.0;
  bool ok = true;  // gates: crossed in the right direction; docks: the target dock
};

struct CourseResult {
  std::string name;
  double start_s = 0.0;
  double end_s = -1.0;  // -1 = not left / not finished
  double time_limit_s = 0.0;
  bool timed_out = false;
  int collisions = 0;  // penalised collisions in this course
  double penalty_s = 0.0;
};

struct ScoreResult {
  std::string course;
  Rules rules = Rules::k2022Hopping;
  double elapsed_s = 0.0;  // run time until completion (or the end of the run)
  bool completed = false;
  bool timed_out = false;
  std::vector<Contact> contacts;
  std::vector<Passage> waypoints;
  std::vector<Passage> gates;
  std::vector<Passage> docks;
  std::vector<CourseResult> courses;
  int collisions = 0;  // penalised collisions
  double penalty_s = 0.0;
  bool recognised = false;        // 2026: the LED showed the target colour first
  double buoy_circled_deg = 0.0;  // 2026: angle swept around the purple buoy (+ clockwise)
  bool circled = false;           // 2026: a full turn around the purple buoy
  bool docked = false;            // entered the target dock (2022) / the dock (2026)
  double bonus_points = 0.0;
  double score_s = 0.0;   // elapsed + penalties: lower is better
  bool pinned = false;    // the run ended with the hull stuck against an obstacle
  std::string pinned_to;  // that obstacle
  double pinned_since_s = 0.0;
  /// The first thing the rules still wanted when the run ended ("" when completed): "gate
  /// finish", "waypoint wp2", "the target dock", "the circle round the purple buoy".
  std::string pending;
};

/// Why a run failed, in words ("" when it passed: completed in time, and for 2026 circled).
/// `mission_finished`: the mission declared itself done (then a goal still pending is one the
/// judge, on the true track, saw missed).
std::string failure_reason(const ScoreResult& result, bool mission_finished);

nlohmann::json to_json(const ScoreResult& result);

struct ScoringOptions {
  double touch_m = 1e-3;         // a contact starts when the hull is this close (numerical touch)
  double release_m = 0.05;       // a contact ends once the hull is this far clear again
  double pinned_s = 30.0;        // pinned: this long in one contact... (0 = never ends a run)
  double pinned_radius_m = 2.0;  // ...without moving this far from where the boat was
};

class Scorer {
 public:
  Scorer(const world::World& world, const config::HullConfig& hull, ScoringOptions options = {});

  /// Judges one truth state (call every dynamics step) and the LED the Arduino shows.
  void update(const dynamics::TruthState& truth, msg::LedColour led);
  /// True once the run is complete or out of time: the runner stops.
  [[nodiscard]] bool done() const { return done_; }
  /// Ends the run at `t_s` when the boat stops sailing before the rules end it (the mission
  /// finished, or the run was cut short): elapsed time, course ends, score and bonuses are settled
  /// as at completion. No-op once done.
  void finish(double t_s) {
    if (!done_) conclude(t_s);
  }
  /// The result so far (final after done() or at the end of the run).
  [[nodiscard]] const ScoreResult& result() const { return result_; }
  /// Distance from the hull outline at `pose` to obstacle i (<= 0 = touching), for tests.
  [[nodiscard]] double clearance_m(std::size_t obstacle, const core::NavPose& pose) const;
  [[nodiscard]] std::size_t obstacle_count() const { return obstacles_.size(); }

 private:
  struct Obstacle {
    std::string name;
    ObstacleKind kind;
    std::vector<std::pair<core::NavPoint, core::NavPoint>> segments;
    core::NavPoint center;  // buoys
    double radius_m = 0.0;
    bool in_contact = false;
    core::NavPoint anchor;  // where the CG was when the contact (or its last 2 m) began
    double anchor_s = 0.0;
    // A circle holding every segment (walls and docks), for passing over far ones cheaply.
    core::NavPoint bound_center;
    double bound_radius_m = 0.0;
  };
  [[nodiscard]] double fraction_inside(const core::NavPose& pose, const auto& inside) const;
  void finish_course(std::size_t index, double t_s);
  void conclude(double t_s);
  [[nodiscard]] std::string pending_goal() const;

  const world::World* world_;
  config::HullConfig hull_;
  ScoringOptions options_;
  std::vector<Obstacle> obstacles_;
  std::vector<core::BodyPoint> samples_;  // grid over the hull area
  double outline_radius_m_ = 0.0;         // farthest outline corner from the body origin
  double samples_radius_m_ = 0.0;         // farthest sample from the body origin
  ScoreResult result_;
  std::size_t next_waypoint_ = 0;
  std::size_t next_gate_ = 0;
  std::size_t course_ = 0;
  bool have_prev_ = false;
  core::NavPoint prev_cg_;
  bool led_decided_ = false;
  int purple_ = -1;  // index of the 2026 purple buoy, -1 = none
  double purple_bearing_deg_ = 0.0;
  bool have_bearing_ = false;
  bool done_ = false;
};

/// An SVG picture of a run: regions, walls, docks (target marked), buoys in their colours, gates,
/// waypoint circles (filled when reached), the path, contacts as red crosses, the final hull.
/// `path` holds body-origin poses in time order (any decimation).
std::string trajectory_svg(const world::World& world, const config::HullConfig& hull,
                           const std::vector<core::NavPose>& path, const ScoreResult* result);

}  // namespace coxswain::sim::scoring
