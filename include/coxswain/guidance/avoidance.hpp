// SPDX-License-Identifier: Apache-2.0
#pragma once
// Reactive obstacle avoidance over one angle-bin representation (docs/missions.md):
// selection-based (the 2022 race algorithm), score-based (2022) and 2026 risk bins, plus a
// deliberately faithful reproduction of the 2022 code's defects for comparison in the simulator.
// Source: the KABOAT 2022 report section 5.2.3-5.2.4 and 002 (course 1).
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "coxswain/core/time.hpp"
#include "coxswain/guidance/angle_bins.hpp"
#include "coxswain/perception/obstacles.hpp"

namespace coxswain::guidance {

enum class Strategy : std::uint8_t {
  kSelection = 0,  // safe bins only, closest to the goal (the 2022 race algorithm, fixed)
  kScore = 1,      // distance + angle + goal risk, lowest total wins (2022 plan A)
  kRiskBin = 2,    // e^(-gain r + offset) risk per bin against a threshold (2026 plan)
  // The 2022 code as written, defects included: end-angle in-fan test, distance to the segment's
  // first point, fixed angular margin, steer at the goal when everything is blocked, left bias on
  // ties, no hysteresis. Only for showing the difference in simulation; never race with it.
  kSelectionNaive2022 = 3,
};

/// Mission-file names: "selection", "score", "risk_bin", "selection_naive_2022".
[[nodiscard]] const char* to_string(Strategy s);
[[nodiscard]] std::optional<Strategy> parse_strategy(std::string_view name);

/// What to do once even the shrunken detection range leaves no safe bin.
enum class AllBlockedPolicy : std::uint8_t { kStop = 0, kBackOff = 1 };

enum class AvoidanceStatus : std::uint8_t {
  kClear = 0,        // the goal bearing is safe; steering at it
  kAvoiding = 1,     // the goal bearing is blocked; steering at the best safe bin
  kBlockedSlow = 2,  // nothing safe at the full range; found a bin after shrinking it, slowed
  kBlockedStop = 3,  // nothing safe even at the minimum range; stopped
  kBackOff = 4,      // as kBlockedStop, but going astern
};
[[nodiscard]] const char* to_string(AvoidanceStatus s);

/// Which side of the goal bearing the chosen bin lies on.
enum class Side : std::int8_t { kPort = -1, kNone = 0, kStarboard = 1 };

/// Tunables. Angles in degrees (body frame), distances in metres, times in seconds. Defaults are
/// for a ~1 m beam boat at a few knots in a KABOAT pool.
struct AvoidanceParams {
  // Score won the simulator batch (README, Simulator): it ties selection on the obstacle course
  // and beats risk_bin there and on the 2026 course 1.
  Strategy strategy = Strategy::kScore;
  AngleFan fan{};                  // -90..+90 deg in 1 deg bins
  double detection_range_m = 5.0;  // obstacles farther than this are ignored
  double half_beam_m = 0.4;        // half the hull width (a mission takes it from boat.yaml)
  double clearance_m = 0.4;        // extra room kept on each side of the hull

  // Speed: the factor falls linearly from 1 at slow_down_range_m to min_speed_factor.
  double slow_down_range_m = 3.0;
  double min_speed_factor = 1.0;

  // All blocked: slow, shrink the range stepwise, then stop or back off.
  double shrink_factor = 0.6;          // range multiplier per step, in (0, 1)
  double min_detection_range_m = 1.2;  // stop shrinking below this
  double blocked_speed_factor = 0.3;   // speed while steering on a shrunken range
  AllBlockedPolicy all_blocked_policy = AllBlockedPolicy::kStop;
  double back_off_speed_factor = 0.25;  // astern speed (positive number) for kBackOff

  // Hysteresis: keep the previous side unless the other is better by this much (degrees of
  // turn, or the score equivalent), and never switch again within hold_time_s of a switch
  // unless the kept side has no safe bin left. The side is forgotten after hold_time_s clear.
  double hysteresis_deg = 15.0;
  double hold_time_s = 3.0;

  // Score (2022 plan A). Per bin: goal_weight * |turn from goal| / 180 and, for bins an obstacle
  // within range covers, distance_weight * (1 - d / range) + angle_weight * (1 - |bearing| / 180).
  // Bins whose obstacle is closer than score_block_range_m are excluded outright.
  double score_goal_weight = 1.0;
  double score_distance_weight = 1.0;
  double score_angle_weight = 0.3;
  double score_block_range_m = 3.0;

  // Risk bins (2026): risk = min(risk_max, e^(-risk_gain_per_m * d + risk_offset)); a bin is
  // unsafe above risk_threshold (0.005 -> unsafe closer than ~2.5 m).
  double risk_gain_per_m = 2.7;
  double risk_offset = 1.5;
  double risk_max = 100.0;
  double risk_threshold = 0.005;

  // kSelectionNaive2022 only: the fixed margin added to both ends of an obstacle.
  double naive_margin_deg = 10.0;

  // Swept hull (every strategy but the naive one): the bins keep a corridor ahead of the bow,
  // but a boat driven by a stern thruster turns about a pivot point near or ahead of the bow and
  // skids outward, so its sides and stern swing out of the turn, into a buoy the bow has just
  // cleared. Each candidate turn is sailed along an arc (the pivot on a circle of
  // sweep_turn_radius_m, the heading turning with it, sweep_step_deg at a time) and the turn is
  // refused on that side once the hull rectangle (bow_ahead_m ahead of the body origin to
  // hull_length_m behind the bow tip, half_beam_m wide) comes within sweep_clearance_m of an
  // obstacle -- or, for an obstacle already that close, any nearer than it is now. The bins'
  // range is then measured along that path (the arc, then straight on), not along a ray from
  // the bow, over the obstacles within detection_range_m plus the longest arc. Off by default: the
  // documents' algorithms as they are; the obstacle course turns it on
  // (config/missions/obstacle_course.yaml).
  bool sweep_enabled = true;
  double hull_length_m = 1.2;        // bow tip to stern (a mission: boat.yaml's hull)
  double bow_ahead_m = 0.1;          // bow tip ahead of the body origin (boat.yaml's overhang)
  double pivot_ahead_m = 0.4;        // turning pivot ahead of the body origin
  double sweep_turn_radius_m = 2.6;  // radius of the pivot's path in a hard turn
  double sweep_clearance_m = 0.2;    // room kept between the swept hull and obstacles
  double sweep_step_deg = 3.0;       // heading step along the predicted arc
  // Toward the sub-goal of a planned path (a passage the global planner found on its map, with
  // its own clearance), the bins within path_bins of the goal's keep this much room each side
  // instead of clearance_m: a gap met at a slant is narrower across the corridor than it is, and
  // the full margin would refuse the passage the path goes through. Negative: clearance_m.
  // Swept hull only.
  double path_clearance_m = -1.0;
  int path_bins = 2;

  /// Empty when valid, else the first problem found.
  [[nodiscard]] std::optional<std::string> validate() const;
  /// Distance below which the risk-bin risk exceeds the threshold.
  [[nodiscard]] double risk_range_m() const;
};

/// One decision. `danger` is per bin, 0 = free .. 1 = blocked, for the live view.
struct AvoidanceDecision {
  double bearing_body_deg = 0.0;  // where to steer, body frame, (-180, 180]
  double speed_factor = 1.0;      // 1 full ahead, 0 stop, negative astern
  AvoidanceStatus status = AvoidanceStatus::kClear;
  Side side = Side::kNone;
  std::uint8_t shrink_steps = 0;  // how often the range was shrunk this tick
  // Largest turn the swept hull allows on each side (degrees, >= 0; the fan's extent when
  // nothing limits it).
  double sweep_port_deg = 180.0;
  double sweep_starboard_deg = 180.0;
  double effective_range_m = 0.0;             // the range the decision was made with
  double nearest_m = AngleBins::kNoObstacle;  // closest obstacle over the fan (hull-widened)
  std::uint32_t bin_count = 0;
  double bin_min_deg = 0.0;
  double bin_width_deg = 1.0;
  std::array<float, AngleBins::kMaxBins> danger{};
};

/// The avoidance engine. Fixed-size state: the bins, per-bin scratch and the previous choice
/// (side and when it was taken), so a decision depends only on its inputs and that state.
/// Not thread-safe; one instance per tick thread. No allocation in `decide`.
class Avoidance {
 public:
  /// nullopt (and `error` filled when given) if the params are invalid.
  [[nodiscard]] static std::optional<Avoidance> create(const AvoidanceParams& params,
                                                       std::string* error = nullptr);

  /// `goal_bearing_body_deg`: bearing of the goal relative to the bow (psi_g), + starboard.
  /// `now`: tick time, used only for the hold time.
  /// `planned_goal`: the goal is a planned path's sub-goal (path_clearance_m applies).
  [[nodiscard]] AvoidanceDecision decide(const perception::ObstacleList& obstacles,
                                         double goal_bearing_body_deg, core::TimeNs now,
                                         bool planned_goal = false);
  /// Forgets the previous choice (new mission leg).
  void reset();
  /// Largest turn, up to `turn_deg` (at most 180), that the swept hull allows to `side`, tested
  /// on `obstacles`, which must be the list the last decide() saw. Beyond the fan's extent too:
  /// for a manoeuvre (a turn back along a path) rather than a bin. `turn_deg` when the sweep is
  /// off (nothing to tell).
  [[nodiscard]] double turn_room_deg(const perception::ObstacleList& obstacles, Side side,
                                     double turn_deg);
  /// Least distance from the obstacles to the water astern: a box the hull's width and `look_m`
  /// long behind the stern. AngleBins::kNoObstacle when nothing is near it.
  [[nodiscard]] double astern_room_m(const perception::ObstacleList& obstacles,
                                     double look_m) const;

  [[nodiscard]] const AvoidanceParams& params() const { return params_; }
  [[nodiscard]] const AngleBins& bins() const { return bins_; }
  /// How far the boat sails along bin `bin`'s predicted path (the turn onto its heading, then
  /// straight on) before an obstacle of the last decide()'s list comes within the hull's
  /// corridor; that decide's starting range where none does (the detection range, or
  /// AngleBins::kNoObstacle for the risk bins). Valid with the swept hull on.
  [[nodiscard]] double path_range_m(std::size_t bin) const { return geometry_range_m_[bin]; }

 private:
  explicit Avoidance(const AvoidanceParams& params);

  // Fills cost_ for range limit `limit_m`; returns true when at least one bin is allowed.
  bool compute_costs(double limit_m);
  // Sets sweep_port_deg_ / sweep_starboard_deg_ from the obstacles (swept-hull check).
  void compute_sweep(const perception::ObstacleList& obstacles);
  // Largest allowed turn on one side (side 0 = port, 1 = starboard) over the segments that
  // compute_sweep() gathered.
  [[nodiscard]] double sweep_turn_limit(const perception::ObstacleList& obstacles, int side);
  // The first of the side's first `steps` steps at which a gathered segment comes within its
  // room of the hull box; `steps` when none does.
  [[nodiscard]] std::size_t first_sweep_hit(const perception::ObstacleList& obstacles, int side,
                                            std::size_t steps);
  // Fills range_m_: per bin, how far the boat sails along its predicted path (the arc to the
  // bin's heading, then straight) before an obstacle comes within half_beam_m + clearance_m of
  // the centre line; the bins' straight-ray range when the sweep is off.
  void compute_path_ranges(const perception::ObstacleList& obstacles);
  // Whether the path ranges are read only as "below the detection range or not" (every
  // strategy but the risk bins), and so where each bin's range starts.
  [[nodiscard]] bool path_ranges_capped() const { return params_.strategy != Strategy::kRiskBin; }
  [[nodiscard]] double path_range_start_m() const {
    return path_ranges_capped() ? params_.detection_range_m : AngleBins::kNoObstacle;
  }
  // Lowers range_m_[j] to where the segment a-b enters bin j's corridor (half-width w).
  void path_range_exact(std::size_t j, double af, double as, double bf, double bs, double w);
  // How far along bin j's predicted path the segment a-b enters its corridor (half-width w);
  // infinity when it never does.
  [[nodiscard]] double corridor_entry_m(std::size_t j, double af, double as, double bf, double bs,
                                        double w) const;
  // Widens the bins near the goal's to the planned path's corridor (path_clearance_m).
  void open_path_bins(const perception::ObstacleList& obstacles, std::size_t goal_bin);
  // Calls path_range_exact for the bins a segment may lower: those its bounding circle (middle,
  // half length) comes near, by the culling tests in floats.
  void cull_path_ranges(double af, double as, double bf, double bs, double w, bool capped);
  [[nodiscard]] bool swept_out(double center_deg) const {
    return center_deg > sweep_starboard_deg_ || -center_deg > sweep_port_deg_;
  }
  void fill_danger(AvoidanceDecision& d, double limit_m) const;
  [[nodiscard]] std::size_t best_in(std::size_t first, std::size_t last, double goal_deg) const;
  [[nodiscard]] double free_room(Side side, double window_deg, double limit_m) const;
  [[nodiscard]] std::size_t most_open_bin(double goal_deg) const;
  [[nodiscard]] double speed_for(double nearest_m) const;
  void decide_naive(const perception::ObstacleList& obstacles, AvoidanceDecision& out);

  AvoidanceParams params_;
  AngleBins bins_;
  std::array<double, AngleBins::kMaxBins> cost_{};  // +inf = not allowed
  // Per bin, set up once: its centre, and the score's angle term (the same expression as ever).
  std::array<double, AngleBins::kMaxBins> center_deg_{};
  std::array<double, AngleBins::kMaxBins> angle_term_{};
  double goal_deg_ = 0.0;          // goal for the current decision
  double cost_per_deg_ = 1.0;      // converts hysteresis_deg into cost units
  double sweep_port_deg_ = 180.0;  // largest turn the swept hull allows
  double sweep_starboard_deg_ = 180.0;
  // Per bin: the range the strategies use, and the pose at the end of the turn onto the bin's
  // heading (origin forward/starboard, cos/sin of the turn, arc length), set up once.
  std::array<double, AngleBins::kMaxBins> range_m_{};
  std::array<double, AngleBins::kMaxBins> arc_end_f_m_{};
  std::array<double, AngleBins::kMaxBins> arc_end_s_m_{};
  std::array<double, AngleBins::kMaxBins> arc_cos_{};
  std::array<double, AngleBins::kMaxBins> arc_sin_{};
  std::array<double, AngleBins::kMaxBins> arc_len_m_{};
  double path_reach_m_ = 0.0;  // farthest a segment can lie and still matter to the path ranges
  // The swept hull's predicted poses depend on the boat alone, so they are set up once: per
  // side, each step's heading change (degrees), cos/sin of the turn and the body origin's
  // position, all in the body frame of now; the hull box's centre at that pose; the turning
  // centre. The motion is a rotation about the turning centre, so a segment whose distances
  // from it never meet the hull box's (plus the room) cannot be touched at any step.
  static constexpr std::size_t kMaxSweepSteps = 361;  // 180 deg in sweep_step_deg >= 0.5
  struct SweepSide {
    std::size_t steps = 0;      // the steps within max_turn_deg (the fan's extent)
    std::size_t all_steps = 0;  // the steps of a turn of 180 deg
    double max_turn_deg = 0.0;
    double centre_f_m = 0.0;  // turning centre
    double centre_s_m = 0.0;
    double box_near_m = 0.0;  // hull box's nearest and farthest points from the centre
    double box_far_m = 0.0;
    std::array<double, kMaxSweepSteps> a_deg{};
    std::array<double, kMaxSweepSteps> cos{};
    std::array<double, kMaxSweepSteps> sin{};
    std::array<double, kMaxSweepSteps> origin_f_m{};
    std::array<double, kMaxSweepSteps> origin_s_m{};
    // The hull box's centre, as floats for the culling test four steps at a time; steps past
    // the last lie far off.
    std::array<float, (kMaxSweepSteps + 3) / 4 * 4> lane_box_f_m{};
    std::array<float, (kMaxSweepSteps + 3) / 4 * 4> lane_box_s_m{};
  };
  std::array<SweepSide, 2> sweep_sides_{};
  double box_radius_m_ = 0.0;  // hull box centre to a corner
  // Scratch for the swept-hull check: the segments within reach and the room each must keep;
  // those a side must test.
  std::array<std::uint16_t, perception::ObstacleList::kMaxSegments> sweep_index_{};
  std::array<double, perception::ObstacleList::kMaxSegments> sweep_room_m_{};
  std::array<std::uint16_t, perception::ObstacleList::kMaxSegments> side_index_{};
  std::size_t sweep_count_ = 0;
  // Blocks of neighbouring bins for the path ranges' first, coarse test.
  static constexpr std::size_t kBlockBins = 8;
  std::size_t block_count_ = 0;
  // The culling tests run four blocks, then four bins (or four swept-hull steps), at a time in
  // floats, with margins far above float rounding: so a culled bin is one the exact test would
  // have left as it was. A segment with an end beyond 100 m (or a boat whose turns reach past
  // it) is tested exactly instead.
  static constexpr std::size_t kBlockLanes = (AngleBins::kMaxBins / kBlockBins + 4) / 4 * 4;
  // A block's bins' corridors all lie in the wedge between its first and last bin's
  // directions, from its first bin's arc end, widened by its farthest other arc end (while the
  // directions turn one way through the block; otherwise every bin of it is tested).
  struct BlockLanes {
    std::array<float, kBlockLanes> origin_f_m{};  // arc end of the block's first bin
    std::array<float, kBlockLanes> origin_s_m{};
    // The detection range less the block's shortest arc (at least 0), plus radius_m: the bound
    // less the segment's own.
    std::array<float, kBlockLanes> reach_m{};
    std::array<float, kBlockLanes> radius_m{};  // farthest arc end of the block from its origin
    std::array<float, kBlockLanes> lo_cos{};    // direction of its first bin
    std::array<float, kBlockLanes> lo_sin{};
    std::array<float, kBlockLanes> hi_cos{};  // direction of its last bin
    std::array<float, kBlockLanes> hi_sin{};
    std::array<std::int32_t, kBlockLanes> wedge{};  // all ones where the wedge test is usable
    std::array<std::int32_t, kBlockLanes> live{};   // all ones for the blocks that exist
  };
  struct BinLanes {  // the per-bin arrays above as floats; bins past the last never pass
    std::array<float, AngleBins::kMaxBins> arc_end_f_m{};
    std::array<float, AngleBins::kMaxBins> arc_end_s_m{};
    std::array<float, AngleBins::kMaxBins> cos{};
    std::array<float, AngleBins::kMaxBins> sin{};
    std::array<float, AngleBins::kMaxBins> arc_len_m{};
    std::array<float, AngleBins::kMaxBins> range_m{};  // range_m_ as it is lowered
  };
  BlockLanes block_lanes_{};
  BinLanes bin_lanes_{};
  bool lanes_usable_ = false;  // every arc end, arc, step and detection range within 100 m
  // What decide() derives from the obstacles alone (bins, swept-hull limits, path ranges),
  // kept for the next call: between two scans the mission decides every tick on the same list
  // with a new goal, and only the choice among the bins has to be made again. Reused only when
  // every segment's end points are the same bit for bit.
  [[nodiscard]] bool same_geometry(const perception::ObstacleList& obstacles) const;
  bool geometry_valid_ = false;
  // The planned path's corridor ranges (open_path_bins) per bin, each valid while its stamp is
  // the geometry's: the goal's bearing drifts a bin or two between scans, so a tick between
  // scans reuses them.
  std::uint64_t geometry_stamp_ = 1;
  std::array<double, AngleBins::kMaxBins> narrow_range_m_{};
  std::array<std::uint64_t, AngleBins::kMaxBins> narrow_stamp_{};
  bool bins_filled_ = false;  // bins_ hold the ranges of the obstacles last decided on
  std::uint32_t geometry_count_ = 0;
  std::array<std::array<double, 4>, perception::ObstacleList::kMaxSegments> geometry_segments_{};
  std::array<double, AngleBins::kMaxBins> geometry_range_m_{};
  double geometry_sweep_port_deg_ = 180.0;
  double geometry_sweep_starboard_deg_ = 180.0;
  double geometry_nearest_m_ = AngleBins::kNoObstacle;
  Side prev_side_ = Side::kNone;
  core::TimeNs side_since_ns_ = core::kNeverNs;  // when prev_side_ was last switched to
  core::TimeNs side_used_ns_ = core::kNeverNs;   // last tick prev_side_ was steered on
};

}  // namespace coxswain::guidance
