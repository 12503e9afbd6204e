// SPDX-License-Identifier: Apache-2.0
// Every parameter of every struct, once. Bounds are what the engine accepts and what makes
// physical sense on a 1-2 m boat; the file, live tuning and the schema all use these.
#include "coxswain/config/param_tables.hpp"

#include <array>

#include "coxswain/core/time.hpp"

namespace coxswain::config {
namespace {

using core::bool_param;
using core::enum_param;
using core::int_param;
using core::ParamChoice;
using core::ParamSpec;
using core::real_param;
using core::text_param;

constexpr bool kLive = true;
constexpr bool kFixed = false;
constexpr double kBig = 1e6;  // "no practical limit" for lengths and times

constexpr std::array kColours{
    ParamChoice{"unknown", static_cast<int>(msg::Colour::kUnknown)},
    ParamChoice{"red", static_cast<int>(msg::Colour::kRed)},
    ParamChoice{"green", static_cast<int>(msg::Colour::kGreen)},
    ParamChoice{"blue", static_cast<int>(msg::Colour::kBlue)},
    ParamChoice{"yellow", static_cast<int>(msg::Colour::kYellow)},
    ParamChoice{"orange", static_cast<int>(msg::Colour::kOrange)},
    ParamChoice{"purple", static_cast<int>(msg::Colour::kPurple)},
    ParamChoice{"black", static_cast<int>(msg::Colour::kBlack)},
    ParamChoice{"white", static_cast<int>(msg::Colour::kWhite)},
};

// ---- engines ------------------------------------------------------------------------------

using control::HeadingPidParams;
constexpr std::array kHeadingPid{
    real_param<HeadingPidParams, &HeadingPidParams::kp_per_deg>(
        "kp_per_deg", "1/deg", 0.0, 1.0, kLive, "turn command per degree of heading error"),
    real_param<HeadingPidParams, &HeadingPidParams::ki_per_deg_s>("ki_per_deg_s", "1/(deg*s)", 0.0,
                                                                  0.5, kLive, "integral gain"),
    real_param<HeadingPidParams, &HeadingPidParams::kd_per_dps>(
        "kd_per_dps", "1/(deg/s)", 0.0, 1.0, kLive,
        "derivative gain, per deg/s of the measured yaw rate"),
    real_param<HeadingPidParams, &HeadingPidParams::output_limit>(
        "output_limit", "", 0.05, 1.0, kLive, "limit of the turn command's magnitude"),
    real_param<HeadingPidParams, &HeadingPidParams::integral_zone_deg>(
        "integral_zone_deg", "deg", 1e-3, 180.0, kLive,
        "the integral runs only within this heading error"),
    real_param<HeadingPidParams, &HeadingPidParams::integral_limit>(
        "integral_limit", "", 0.0, 1.0, kLive, "clamp on the integral term's contribution"),
    real_param<HeadingPidParams, &HeadingPidParams::tracking_gain_per_s>(
        "tracking_gain_per_s", "1/s", 0.0, 100.0, kLive,
        "back-calculation gain that bleeds the integral while saturated"),
    real_param<HeadingPidParams, &HeadingPidParams::derivative_tau_s>(
        "derivative_tau_s", "s", 0.0, 10.0, kLive,
        "low-pass of the heading-difference rate when no gyro rate is given"),
    real_param<HeadingPidParams, &HeadingPidParams::max_dt_s>(
        "max_dt_s", "s", 1e-3, 10.0, kLive,
        "a longer gap between steps (a dropout) skips integration and derivative"),
    real_param<HeadingPidParams, &HeadingPidParams::reversal_hold_deg>(
        "reversal_hold_deg", "deg", 0.0, 89.0, kLive,
        "near 180 deg of error, keep the turn's side unless the error crosses this much"),
};

using control::SpeedScheduleParams;
constexpr std::array kSpeed{
    real_param<SpeedScheduleParams, &SpeedScheduleParams::min_thrust_frac>(
        "min_thrust_frac", "", 0.0, 1.0, kLive, "thrust at or inside slow_distance_m"),
    real_param<SpeedScheduleParams, &SpeedScheduleParams::max_thrust_frac>(
        "max_thrust_frac", "", 0.0, 1.0, kLive, "thrust at or beyond fast_distance_m"),
    real_param<SpeedScheduleParams, &SpeedScheduleParams::slow_distance_m>(
        "slow_distance_m", "m", 0.0, 50.0, kLive, "distance to go below which thrust is minimal"),
    real_param<SpeedScheduleParams, &SpeedScheduleParams::fast_distance_m>(
        "fast_distance_m", "m", 0.0, 100.0, kLive, "distance to go beyond which thrust is maximal"),
    real_param<SpeedScheduleParams, &SpeedScheduleParams::rise_per_s>(
        "rise_per_s", "1/s", 0.01, 10.0, kLive, "thrust increase limit, fraction per second"),
    real_param<SpeedScheduleParams, &SpeedScheduleParams::fall_per_s>(
        "fall_per_s", "1/s", 0.01, 10.0, kLive, "thrust decrease limit, fraction per second"),
    real_param<SpeedScheduleParams, &SpeedScheduleParams::cruise_thrust_frac>(
        "cruise_thrust_frac", "", 0.0, 1.0, kFixed,
        "thrust of the avoidance tasks before the avoidance's speed factor"),
};

using guidance::AvoidanceParams;
constexpr std::array kStrategies{
    ParamChoice{"selection", static_cast<int>(guidance::Strategy::kSelection)},
    ParamChoice{"score", static_cast<int>(guidance::Strategy::kScore)},
    ParamChoice{"risk_bin", static_cast<int>(guidance::Strategy::kRiskBin)},
    // The 2022 code with its defects: for comparison in the simulator, never chosen live.
    ParamChoice{"selection_naive_2022", static_cast<int>(guidance::Strategy::kSelectionNaive2022),
                false},
};
constexpr std::array kAllBlocked{
    ParamChoice{"stop", static_cast<int>(guidance::AllBlockedPolicy::kStop)},
    ParamChoice{"back_off", static_cast<int>(guidance::AllBlockedPolicy::kBackOff)},
};
constexpr std::array kAvoidance{
    enum_param<AvoidanceParams, &AvoidanceParams::strategy>(
        "strategy", kStrategies, kLive,
        "bin choice: selection, score (2022 plan A), risk_bin (2026 plan) or the 2022 code "
        "as written (simulator comparison only)"),
    real_param<AvoidanceParams, &AvoidanceParams::fan, &guidance::AngleFan::min_deg>(
        "fan_min_deg", "deg", -180.0, 180.0, kFixed, "first candidate heading, body frame"),
    real_param<AvoidanceParams, &AvoidanceParams::fan, &guidance::AngleFan::max_deg>(
        "fan_max_deg", "deg", -180.0, 180.0, kFixed, "last candidate heading, body frame"),
    real_param<AvoidanceParams, &AvoidanceParams::fan, &guidance::AngleFan::bin_width_deg>(
        "bin_width_deg", "deg", 0.1, 90.0, kFixed, "width of one candidate-heading bin"),
    real_param<AvoidanceParams, &AvoidanceParams::detection_range_m>(
        "detection_range_m", "m", 0.5, 30.0, kLive, "obstacles farther than this are ignored"),
    real_param<AvoidanceParams, &AvoidanceParams::clearance_m>(
        "clearance_m", "m", 0.0, 2.0, kLive,
        "extra room kept on each side of the hull (its width is boat.yaml's hull.beam_m)"),
    real_param<AvoidanceParams, &AvoidanceParams::slow_down_range_m>(
        "slow_down_range_m", "m", 0.1, 20.0, kLive,
        "speed factor falls linearly from 1 at this range of the nearest obstacle"),
    real_param<AvoidanceParams, &AvoidanceParams::min_speed_factor>(
        "min_speed_factor", "", 0.0, 1.0, kLive, "speed factor at the nearest ranges"),
    real_param<AvoidanceParams, &AvoidanceParams::shrink_factor>(
        "shrink_factor", "", 0.05, 0.95, kLive,
        "all bins blocked: range multiplier per shrinking step"),
    real_param<AvoidanceParams, &AvoidanceParams::min_detection_range_m>(
        "min_detection_range_m", "m", 0.1, 30.0, kLive, "the range is not shrunk below this"),
    real_param<AvoidanceParams, &AvoidanceParams::blocked_speed_factor>(
        "blocked_speed_factor", "", 0.0, 1.0, kLive, "speed while steering on a shrunken range"),
    enum_param<AvoidanceParams, &AvoidanceParams::all_blocked_policy>(
        "all_blocked", kAllBlocked, kLive,
        "nothing safe even at the minimum range: stop, or back off"),
    real_param<AvoidanceParams, &AvoidanceParams::back_off_speed_factor>(
        "back_off_speed_factor", "", 0.0, 1.0, kLive, "astern speed when backing off"),
    real_param<AvoidanceParams, &AvoidanceParams::hysteresis_deg>(
        "hysteresis_deg", "deg", 0.0, 90.0, kLive,
        "keep the previous side unless the other is better by this much"),
    real_param<AvoidanceParams, &AvoidanceParams::hold_time_s>(
        "hold_time_s", "s", 0.0, 10.0, kLive,
        "no second side switch within this time, unless the kept side is blocked"),
    real_param<AvoidanceParams, &AvoidanceParams::score_goal_weight>(
        "score.goal_weight", "", 0.01, 10.0, kLive, "score: weight of the turn from the goal"),
    real_param<AvoidanceParams, &AvoidanceParams::score_distance_weight>(
        "score.distance_weight", "", 0.0, 10.0, kLive, "score: weight of an obstacle's nearness"),
    real_param<AvoidanceParams, &AvoidanceParams::score_angle_weight>(
        "score.angle_weight", "", 0.0, 10.0, kLive, "score: weight of an obstacle's bearing"),
    real_param<AvoidanceParams, &AvoidanceParams::score_block_range_m>(
        "score.block_range_m", "m", 0.0, 30.0, kLive,
        "score: bins with an obstacle nearer than this are excluded"),
    real_param<AvoidanceParams, &AvoidanceParams::risk_gain_per_m>(
        "risk.gain_per_m", "1/m", 0.01, 20.0, kLive, "risk bins: decay of risk with range"),
    real_param<AvoidanceParams, &AvoidanceParams::risk_offset>(
        "risk.offset", "", -10.0, 10.0, kLive, "risk bins: offset of the exponent"),
    real_param<AvoidanceParams, &AvoidanceParams::risk_max>("risk.max", "", 0.001, 1000.0, kLive,
                                                            "risk bins: cap of one bin's risk"),
    real_param<AvoidanceParams, &AvoidanceParams::risk_threshold>(
        "risk.threshold", "", 1e-6, 100.0, kLive, "risk bins: a bin above this is unsafe"),
    real_param<AvoidanceParams, &AvoidanceParams::naive_margin_deg>(
        "naive_margin_deg", "deg", 0.0, 90.0, kLive,
        "the 2022 code's fixed margin on both ends of an obstacle"),
    bool_param<AvoidanceParams, &AvoidanceParams::sweep_enabled>(
        "sweep.enabled", kLive, "sail each candidate turn along a predicted arc (swept hull)"),
    real_param<AvoidanceParams, &AvoidanceParams::pivot_ahead_m>(
        "sweep.pivot_ahead_m", "m", -10.0, 10.0, kLive,
        "swept hull: turning pivot ahead of the body origin"),
    real_param<AvoidanceParams, &AvoidanceParams::sweep_turn_radius_m>(
        "sweep.turn_radius_m", "m", 0.0, 50.0, kLive,
        "swept hull: radius of the pivot's path in a hard turn"),
    real_param<AvoidanceParams, &AvoidanceParams::sweep_clearance_m>(
        "sweep.clearance_m", "m", 0.0, 2.0, kLive,
        "swept hull: room kept between the hull and obstacles"),
    real_param<AvoidanceParams, &AvoidanceParams::sweep_step_deg>(
        "sweep.step_deg", "deg", 0.5, 45.0, kLive, "swept hull: heading step along the arc"),
    real_param<AvoidanceParams, &AvoidanceParams::path_clearance_m>(
        "path_clearance_m", "m", -1.0, 2.0, kLive,
        "toward a planned path's sub-goal, the room kept each side of the hull in the bins near "
        "its bearing (negative: clearance_m)"),
    int_param<AvoidanceParams, &AvoidanceParams::path_bins>(
        "path_bins", "", 0, 45, kLive,
        "bins either side of a planned sub-goal's bearing that take path_clearance_m"),
};

using guidance::LineFollowParams;
using guidance::WaypointFollowerParams;
constexpr std::array kWaypoints{
    real_param<WaypointFollowerParams, &WaypointFollowerParams::arrival_radius_m>(
        "arrival_radius_m", "m", 0.05, 100.0, kFixed, "a waypoint this near is reached"),
    real_param<WaypointFollowerParams, &WaypointFollowerParams::arrival_confidence>(
        "arrival_confidence", "", 0.0, 0.999, kFixed,
        "with the filter's covariance: how sure the estimate must be (0, or 0.5 and up; 0 = "
        "arrival_radius_m always); also the margin inside a gate's ends"),
    real_param<WaypointFollowerParams, &WaypointFollowerParams::rule_radius_m>(
        "rule_radius_m", "m", 0.05, 100.0, kFixed,
        "the rules' circle at the antenna, judged with arrival_confidence"),
    real_param<WaypointFollowerParams, &WaypointFollowerParams::slip_radius_m>(
        "slip_radius_m", "m", 0.05, 100.0, kFixed,
        "passing a waypoint within this, moving away, also counts"),
    bool_param<WaypointFollowerParams, &WaypointFollowerParams::line_following>(
        "line_following", kFixed, "follow the line between waypoints (ILOS), not the bearing"),
    real_param<WaypointFollowerParams, &WaypointFollowerParams::line,
               &LineFollowParams::lookahead_m>("lookahead_m", "m", 0.1, 100.0, kFixed,
                                               "line of sight: look-ahead along the line"),
    real_param<WaypointFollowerParams, &WaypointFollowerParams::line,
               &LineFollowParams::integral_gain>("integral_gain", "", 0.0, 10.0, kFixed,
                                                 "line of sight: integral gain (0 = plain LOS)"),
    real_param<WaypointFollowerParams, &WaypointFollowerParams::line,
               &LineFollowParams::max_integral_m>("max_integral_m", "m", 0.0, 50.0, kFixed,
                                                  "line of sight: integral term's limit"),
    real_param<WaypointFollowerParams, &WaypointFollowerParams::line, &LineFollowParams::max_dt_s>(
        "max_dt_s", "s", 1e-3, 10.0, kFixed, "line of sight: longer steps are not integrated"),
};

using guidance::GpsCalibrationParams;
constexpr std::array kGpsCalibration{
    int_param<GpsCalibrationParams, &GpsCalibrationParams::min_fixes>(
        "min_fixes", "", 1, 256, kFixed, "fewer fixes on the start point: refuse to calibrate"),
    int_param<GpsCalibrationParams, &GpsCalibrationParams::window>(
        "window", "", 1, 256, kFixed, "the last this many fixes are averaged"),
    real_param<GpsCalibrationParams, &GpsCalibrationParams::max_spread_m>(
        "max_spread_m", "m", 1e-3, 100.0, kFixed,
        "a fix farther than this from the mean: moving, or bad GNSS"),
    real_param<GpsCalibrationParams, &GpsCalibrationParams::max_offset_m>(
        "max_offset_m", "m", 1e-3, 1000.0, kFixed,
        "a larger offset means the wrong start point or frame: refuse"),
};

using perception::HullBox;
using perception::LidarClusterParams;
constexpr std::array kClustering{
    real_param<LidarClusterParams, &LidarClusterParams::group_gap_m>(
        "group_gap_m", "m", 0.01, 2.0, kLive, "neighbouring returns closer than this group"),
    real_param<LidarClusterParams, &LidarClusterParams::group_gap_per_m>(
        "group_gap_per_m", "m/m", 0.0, 0.5, kLive, "group gap growth per metre of range"),
    int_param<LidarClusterParams, &LidarClusterParams::min_group_points>(
        "min_group_points", "", 1, 100, kLive, "smaller groups are dropped as noise"),
    real_param<LidarClusterParams, &LidarClusterParams::split_distance_m>(
        "split_distance_m", "m", 0.01, 2.0, kLive,
        "a group splits where a return is this far off its chord"),
    real_param<LidarClusterParams, &LidarClusterParams::split_distance_per_m>(
        "split_distance_per_m", "m/m", 0.0, 0.5, kLive, "split distance growth per metre"),
    int_param<LidarClusterParams, &LidarClusterParams::min_split_points>(
        "min_split_points", "", 1, 4096, kLive, "groups with fewer returns are not split"),
    real_param<LidarClusterParams, &LidarClusterParams::wall_min_length_m>(
        "wall_min_length_m", "m", 0.05, 10.0, kLive, "a longer segment is a wall, not a buoy"),
    real_param<LidarClusterParams, &LidarClusterParams::wall_piece_max_length_m>(
        "wall_piece_max_length_m", "m", 0.05, 100.0, kLive,
        "walls are cut into pieces at most this long"),
    real_param<LidarClusterParams, &LidarClusterParams::min_range_m>(
        "min_range_m", "m", 0.0, 10.0, kLive, "nearer returns are dropped"),
    real_param<LidarClusterParams, &LidarClusterParams::max_range_m>(
        "max_range_m", "m", 1.0, 40.0, kLive, "farther returns are dropped"),
    real_param<LidarClusterParams, &LidarClusterParams::hull, &HullBox::forward_min_m>(
        "hull_box.forward_min_m", "m", -50.0, 50.0, kLive,
        "own-hull box (returns inside are dropped), body frame: aft end"),
    real_param<LidarClusterParams, &LidarClusterParams::hull, &HullBox::forward_max_m>(
        "hull_box.forward_max_m", "m", -50.0, 50.0, kLive, "own-hull box: forward end"),
    real_param<LidarClusterParams, &LidarClusterParams::hull, &HullBox::starboard_min_m>(
        "hull_box.starboard_min_m", "m", -50.0, 50.0, kLive, "own-hull box: port side"),
    real_param<LidarClusterParams, &LidarClusterParams::hull, &HullBox::starboard_max_m>(
        "hull_box.starboard_max_m", "m", -50.0, 50.0, kLive, "own-hull box: starboard side"),
    real_param<LidarClusterParams, &LidarClusterParams::profile_bin_width_deg>(
        "profile_bin_width_deg", "deg", 0.1, 45.0, kLive, "bin width of the range profile"),
    bool_param<LidarClusterParams, &LidarClusterParams::line_fit>(
        "line_fit", kLive, "fit segment ends by least squares (else the end returns)"),
    bool_param<LidarClusterParams, &LidarClusterParams::merge_across_seam>(
        "merge_across_seam", kLive, "join the groups either side of the scan's seam"),
};

using perception::MarkerVoteParams;
constexpr std::array kVisionVote{
    core::scaled_param<MarkerVoteParams>(
        "window_s", "s", 0.05, 600.0, kFixed, "votes older than this are ignored",
        [](const MarkerVoteParams& p) { return core::ns_to_sec(p.window_ns); },
        [](MarkerVoteParams& p, double v) { p.window_ns = core::sec_to_ns(v); }),
    real_param<MarkerVoteParams, &MarkerVoteParams::min_ratio>("min_ratio", "", 0.01, 1.0, kFixed,
                                                               "hits per frame needed to decide"),
    int_param<MarkerVoteParams, &MarkerVoteParams::min_frames>(
        "min_frames", "", 1, 256, kFixed, "fewer frames in the window: undecided"),
    core::scaled_param<MarkerVoteParams>(
        "min_span_s", "s", 0.0, 600.0, kFixed, "the window must hold this much history",
        [](const MarkerVoteParams& p) { return core::ns_to_sec(p.min_span_ns); },
        [](MarkerVoteParams& p, double v) { p.min_span_ns = core::sec_to_ns(v); }),
};

// ---- camera detectors (the vision file) ---------------------------------------------------

using perception::BackgroundParams;
using perception::ColourRange;
using perception::HsvRange;
using perception::ShapeParams;
using perception::VisionParams;
// The colours a range may name (a range without one is no range).
constexpr std::array kRangeColours{
    ParamChoice{"red", static_cast<int>(msg::Colour::kRed)},
    ParamChoice{"orange", static_cast<int>(msg::Colour::kOrange)},
    ParamChoice{"yellow", static_cast<int>(msg::Colour::kYellow)},
    ParamChoice{"green", static_cast<int>(msg::Colour::kGreen)},
    ParamChoice{"blue", static_cast<int>(msg::Colour::kBlue)},
    ParamChoice{"purple", static_cast<int>(msg::Colour::kPurple)},
    ParamChoice{"black", static_cast<int>(msg::Colour::kBlack)},
    ParamChoice{"white", static_cast<int>(msg::Colour::kWhite)},
};
// One entry of the `colours` list. The HSV bounds are live: a venue's light is tuned while the
// boat sails (OpenCV 8-bit: hue 0..179, saturation and value 0..255; h_min > h_max wraps).
constexpr std::array kColourRange{
    enum_param<ColourRange, &ColourRange::colour>("colour", kRangeColours, kFixed,
                                                  "the colour this HSV box finds"),
    int_param<ColourRange, &ColourRange::hsv, &HsvRange::h_min>(
        "h_min", "", 0, 179, kLive, "lowest hue (above h_max: the range wraps through 180/0)"),
    int_param<ColourRange, &ColourRange::hsv, &HsvRange::h_max>("h_max", "", 0, 179, kLive,
                                                                "highest hue"),
    int_param<ColourRange, &ColourRange::hsv, &HsvRange::s_min>("s_min", "", 0, 255, kLive,
                                                                "lowest saturation"),
    int_param<ColourRange, &ColourRange::hsv, &HsvRange::s_max>("s_max", "", 0, 255, kLive,
                                                                "highest saturation"),
    int_param<ColourRange, &ColourRange::hsv, &HsvRange::v_min>("v_min", "", 0, 255, kLive,
                                                                "lowest value (brightness)"),
    int_param<ColourRange, &ColourRange::hsv, &HsvRange::v_max>("v_max", "", 0, 255, kLive,
                                                                "highest value (brightness)"),
    bool_param<ColourRange, &ColourRange::markers>("markers", kFixed,
                                                   "the marker detector searches this colour"),
    bool_param<ColourRange, &ColourRange::buoys>("buoys", kFixed,
                                                 "the buoy detector searches this colour"),
};
constexpr std::array kVision{
    int_param<VisionParams, &VisionParams::blur_kernel_px>(
        "blur_kernel_px", "px", 0, 31, kFixed,
        "Gaussian pre-blur against sensor noise; odd, 0 = off"),
    int_param<VisionParams, &VisionParams::open_kernel_px>(
        "open_kernel_px", "px", 0, 31, kFixed, "morphological opening removes specks; 0 = off"),
    int_param<VisionParams, &VisionParams::close_kernel_px>(
        "close_kernel_px", "px", 0, 31, kFixed, "closing fills glyph holes and pinholes; 0 = off"),
    real_param<VisionParams, &VisionParams::min_area_fraction>(
        "min_area_fraction", "", 1e-7, 0.999, kFixed,
        "smallest marker, fraction of the frame area"),
    real_param<VisionParams, &VisionParams::buoy_min_area_fraction>(
        "buoy_min_area_fraction", "", 1e-7, 0.999, kFixed,
        "smallest buoy, fraction of the frame area"),
    real_param<VisionParams, &VisionParams::buoy_min_solidity>(
        "buoy_min_solidity", "", 0.0, 1.0, kFixed,
        "area / hull area a buoy needs (spray and glare are not round)"),
    int_param<VisionParams, &VisionParams::edge_margin_px>(
        "edge_margin_px", "px", 0, 4096, kFixed,
        "shapes whose box comes this close to the border are cut"),
    bool_param<VisionParams, &VisionParams::buoy_reject_edge>(
        "buoy_reject_edge", kFixed,
        "drop buoys cut by the border (else their bearing still counts)"),
    bool_param<VisionParams, &VisionParams::background, &BackgroundParams::enabled>(
        "background.enabled", kFixed, "model each strip's water or sky colour and reject it"),
    int_param<VisionParams, &VisionParams::background, &BackgroundParams::strips>(
        "background.strips", "", 1, BackgroundParams::kMaxStrips, kFixed,
        "horizontal strips, each with its own model"),
    int_param<VisionParams, &VisionParams::background, &BackgroundParams::sample_step_px>(
        "background.sample_step_px", "px", 1, 64, kFixed, "sampling grid pitch"),
    int_param<VisionParams, &VisionParams::background, &BackgroundParams::max_samples>(
        "background.max_samples", "", 100, 1000000, kFixed,
        "samples per strip at most: a larger frame's grid is coarsened to stay within it"),
    real_param<VisionParams, &VisionParams::background, &BackgroundParams::min_share>(
        "background.min_share", "", 1e-3, 1.0, kFixed,
        "share of a strip's samples the dominant colour must hold"),
    real_param<VisionParams, &VisionParams::background, &BackgroundParams::reject_sigma>(
        "background.reject_sigma", "", 0.0, 10.0, kFixed,
        "Mahalanobis radius rejected around the background colour"),
    real_param<VisionParams, &VisionParams::background, &BackgroundParams::min_sigma>(
        "background.min_sigma", "grey levels", 0.0, 128.0, kFixed,
        "floor of each axis' spread (flat, noiseless water)"),
    real_param<VisionParams, &VisionParams::background, &BackgroundParams::max_sigma>(
        "background.max_sigma", "grey levels", 0.0, 128.0, kFixed,
        "cap of each axis' spread, so a mottled band cannot swallow the markers"),
    int_param<VisionParams, &VisionParams::background, &BackgroundParams::max_saturation>(
        "background.max_saturation", "", 0, 255, kFixed,
        "a more saturated dominant colour is a marker filling the view, not water or sky"),
    real_param<VisionParams, &VisionParams::shape, &ShapeParams::approx_epsilon_fraction>(
        "shape.approx_epsilon_fraction", "", 1e-4, 0.199, kFixed,
        "polygon approximation tolerance, fraction of the perimeter"),
    real_param<VisionParams, &VisionParams::shape, &ShapeParams::convex_min_solidity>(
        "shape.convex_min_solidity", "", 0.0, 1.0, kFixed,
        "area / hull area for a triangle, rectangle or circle"),
    real_param<VisionParams, &VisionParams::shape, &ShapeParams::cross_max_solidity>(
        "shape.cross_max_solidity", "", 0.0, 1.0, kFixed, "a cross is at most this solid"),
    real_param<VisionParams, &VisionParams::shape, &ShapeParams::cross_min_solidity>(
        "shape.cross_min_solidity", "", 0.0, 1.0, kFixed, "a cross is at least this solid"),
    real_param<VisionParams, &VisionParams::shape, &ShapeParams::cross_min_defect_depth>(
        "shape.cross_min_defect_depth", "", 0.0, 1.0, kFixed,
        "a cross's concavities are this deep, fraction of the square root of its area"),
    real_param<VisionParams, &VisionParams::shape, &ShapeParams::triangle_max_extent>(
        "shape.triangle_max_extent", "", 0.0, 1.0, kFixed,
        "a triangle fills at most this share of its smallest rectangle"),
    real_param<VisionParams, &VisionParams::shape, &ShapeParams::rectangle_min_extent>(
        "shape.rectangle_min_extent", "", 0.0, 1.0, kFixed,
        "a rectangle fills at least this share of its smallest rectangle"),
    real_param<VisionParams, &VisionParams::shape, &ShapeParams::circle_min_circularity>(
        "shape.circle_min_circularity", "", 0.0, 1.0, kFixed,
        "a circle's 4 pi area / perimeter^2 on its hull is at least this"),
    real_param<VisionParams, &VisionParams::shape, &ShapeParams::circle_max_extent>(
        "shape.circle_max_extent", "", 0.0, 1.0, kFixed,
        "a circle fills at most this share of its smallest rectangle"),
    real_param<VisionParams, &VisionParams::shape, &ShapeParams::min_fill_ratio>(
        "shape.min_fill_ratio", "", 0.0, 1.0, kFixed,
        "mask pixels / outer-contour area a shape needs (rejects outline rings)"),
    real_param<VisionParams, &VisionParams::shape, &ShapeParams::island_min_hole_fraction>(
        "shape.island_min_hole_fraction", "", 0.0, 1.0, kFixed,
        "a marker inside a hole of a larger blob must fill this share of the hole"),
};

// ---- mission settings ---------------------------------------------------------------------

constexpr std::array kStartModes{
    ParamChoice{"immediate", static_cast<int>(StartMode::kImmediate)},
    ParamChoice{"arduino_switch", static_cast<int>(StartMode::kArduinoSwitch)},
    ParamChoice{"control", static_cast<int>(StartMode::kControl)},
};
constexpr std::array kMission{
    real_param<MissionConfig, &MissionConfig::tick_rate_hz>("tick_rate_hz", "Hz", 1.0, 1000.0,
                                                            kFixed, "rate of the mission tick"),
    enum_param<MissionConfig, &MissionConfig::start_mode>(
        "start.mode", kStartModes, kFixed,
        "what starts the mission: at once, the Arduino's start switch, or the control socket"),
    bool_param<MissionConfig, &MissionConfig::calibrate_gps_at_start>(
        "start.calibrate_gps", kFixed, "measure the GNSS offset on the start point"),
    bool_param<MissionConfig, &MissionConfig::require_arduino>(
        "start.require_arduino", kFixed,
        "autonomy needs a live Arduino in autonomous mode (false: bench runs only)"),
    int_param<MissionConfig, &MissionConfig::lidar_stale_ms>(
        "stale_after_ms.lidar", "ms", 20, 60000, kFixed, "hold when no scan for this long"),
    int_param<MissionConfig, &MissionConfig::imu_stale_ms>(
        "stale_after_ms.imu", "ms", 20, 60000, kFixed, "hold when no IMU sample for this long"),
    int_param<MissionConfig, &MissionConfig::gnss_stale_ms>(
        "stale_after_ms.gnss", "ms", 20, 60000, kFixed, "hold when no usable fix for this long"),
    int_param<MissionConfig, &MissionConfig::arduino_stale_ms>(
        "stale_after_ms.arduino", "ms", 20, 60000, kFixed,
        "hold when no Arduino telemetry for this long"),
    int_param<MissionConfig, &MissionConfig::camera_stale_ms>(
        "stale_after_ms.camera", "ms", 20, 60000, kFixed,
        "camera detections older than this are not used"),
};

constexpr std::array kNavigation{
    real_param<NavigationConfig, &NavigationConfig::heading_filter_tau_s>(
        "heading_filter_tau_s", "s", 0.0, 10.0, kFixed, "low-pass of the IMU heading"),
    real_param<NavigationConfig, &NavigationConfig::position_gain>(
        "position_gain", "", 0.01, 1.0, kFixed,
        "weight of each GNSS fix against the dead-reckoned estimate (1 = raw fixes)"),
    bool_param<NavigationConfig, &NavigationConfig::start_lever_arm>(
        "start_lever_arm", kFixed,
        "the start point marks the body origin: remove the antenna's offset first"),
    bool_param<NavigationConfig, &NavigationConfig::start_drift>(
        "start_drift", kFixed, "take calibration fixes back by the drift while waiting"),
    real_param<NavigationConfig, &NavigationConfig::filter,
               &guidance::NavFilterParams::accel_noise_mps2>(
        "filter.accel_noise_mps2", "m/s^2", 0.0, 10.0, kFixed,
        "unmodelled acceleration (white process noise)"),
    real_param<NavigationConfig, &NavigationConfig::filter,
               &guidance::NavFilterParams::heading_walk_deg_per_sqrt_s>(
        "filter.heading_walk_deg_per_sqrt_s", "deg/sqrt(s)", 0.0, 10.0, kFixed,
        "gyro noise integrated into heading"),
    real_param<NavigationConfig, &NavigationConfig::filter,
               &guidance::NavFilterParams::heading_walk_no_gyro_deg_per_sqrt_s>(
        "filter.heading_walk_no_gyro_deg_per_sqrt_s", "deg/sqrt(s)", 0.0, 200.0, kFixed,
        "heading process noise without a yaw rate"),
    real_param<NavigationConfig, &NavigationConfig::filter,
               &guidance::NavFilterParams::gyro_bias_walk_dps_per_sqrt_s>(
        "filter.gyro_bias_walk_dps_per_sqrt_s", "deg/s/sqrt(s)", 0.0, 1.0, kFixed,
        "yaw-rate bias drift"),
    real_param<NavigationConfig, &NavigationConfig::filter,
               &guidance::NavFilterParams::gnss_bias_wander_sigma_m>(
        "filter.gnss_bias_wander_sigma_m", "m", 0.0, 20.0, kFixed,
        "GNSS bias wander (Gauss-Markov sigma) around its constant part"),
    real_param<NavigationConfig, &NavigationConfig::filter,
               &guidance::NavFilterParams::gnss_bias_tau_s>(
        "filter.gnss_bias_tau_s", "s", 1.0, 1e5, kFixed, "correlation time of that wander"),
    real_param<NavigationConfig, &NavigationConfig::filter,
               &guidance::NavFilterParams::mag_bias_walk_deg_per_sqrt_s>(
        "filter.mag_bias_walk_deg_per_sqrt_s", "deg/sqrt(s)", 0.0, 10.0, kFixed,
        "magnetometer error drift"),
    real_param<NavigationConfig, &NavigationConfig::filter,
               &guidance::NavFilterParams::initial_gnss_bias_sigma_m>(
        "filter.initial_gnss_bias_sigma_m", "m", 0.001, 100.0, kFixed,
        "GNSS bias prior before the start calibration"),
    real_param<NavigationConfig, &NavigationConfig::filter,
               &guidance::NavFilterParams::initial_mag_bias_sigma_deg>(
        "filter.initial_mag_bias_sigma_deg", "deg", 0.001, 90.0, kFixed, "magnetometer bias prior"),
    real_param<NavigationConfig, &NavigationConfig::filter,
               &guidance::NavFilterParams::initial_gyro_bias_sigma_dps>(
        "filter.initial_gyro_bias_sigma_dps", "deg/s", 0.001, 10.0, kFixed, "gyro bias prior"),
    real_param<NavigationConfig, &NavigationConfig::filter,
               &guidance::NavFilterParams::initial_velocity_sigma_mps>(
        "filter.initial_velocity_sigma_mps", "m/s", 0.001, 10.0, kFixed,
        "velocity prior at a first fix without velocity"),
    real_param<NavigationConfig, &NavigationConfig::filter,
               &guidance::NavFilterParams::mag_noise_deg>(
        "filter.mag_noise_deg", "deg", 0.001, 45.0, kFixed, "white magnetometer heading noise"),
    real_param<NavigationConfig, &NavigationConfig::filter,
               &guidance::NavFilterParams::gnss_sigma_floor_m>(
        "filter.gnss_sigma_floor_m", "m", 0.001, 10.0, kFixed,
        "single-point fix: noise floor per axis (hAcc above it)"),
    real_param<NavigationConfig, &NavigationConfig::filter,
               &guidance::NavFilterParams::gnss_float_sigma_floor_m>(
        "filter.gnss_float_sigma_floor_m", "m", 0.001, 10.0, kFixed,
        "RTK float: noise floor per axis"),
    real_param<NavigationConfig, &NavigationConfig::filter,
               &guidance::NavFilterParams::gnss_fixed_sigma_floor_m>(
        "filter.gnss_fixed_sigma_floor_m", "m", 0.001, 10.0, kFixed,
        "RTK fixed: noise floor per axis"),
    real_param<NavigationConfig, &NavigationConfig::filter,
               &guidance::NavFilterParams::gnss_unknown_sigma_m>(
        "filter.gnss_unknown_sigma_m", "m", 0.001, 50.0, kFixed,
        "fix without hAcc (NMEA without GST): noise per axis"),
    real_param<NavigationConfig, &NavigationConfig::filter,
               &guidance::NavFilterParams::gnss_velocity_sigma_mps>(
        "filter.gnss_velocity_sigma_mps", "m/s", 0.001, 5.0, kFixed,
        "GNSS velocity noise per axis: when the fix has no sAcc, and the floor under sAcc / sqrt "
        "2"),
    bool_param<NavigationConfig, &NavigationConfig::filter,
               &guidance::NavFilterParams::cog_heading_update>(
        "filter.cog_heading_update", kFixed,
        "course over ground corrects the heading (a steady current biases it)"),
    real_param<NavigationConfig, &NavigationConfig::filter,
               &guidance::NavFilterParams::cog_min_speed_mps>(
        "filter.cog_min_speed_mps", "m/s", 0.0, 5.0, kFixed,
        "course over ground corrects heading only above this speed"),
    real_param<NavigationConfig, &NavigationConfig::filter,
               &guidance::NavFilterParams::cog_max_yaw_rate_dps>(
        "filter.cog_max_yaw_rate_dps", "deg/s", 0.001, 90.0, kFixed,
        "... and only below this turn rate"),
    real_param<NavigationConfig, &NavigationConfig::filter,
               &guidance::NavFilterParams::cog_crab_sigma_deg>(
        "filter.cog_crab_sigma_deg", "deg", 0.001, 45.0, kFixed,
        "course over ground minus heading at any speed (leeway)"),
    real_param<NavigationConfig, &NavigationConfig::filter,
               &guidance::NavFilterParams::cog_current_mps>(
        "filter.cog_current_mps", "m/s", 0.0, 3.0, kFixed,
        "water current allowed for: course over ground may differ from heading by atan(current / "
        "speed)"),
    real_param<NavigationConfig, &NavigationConfig::filter,
               &guidance::NavFilterParams::cog_interval_s>(
        "filter.cog_interval_s", "s", 0.0, 60.0, kFixed,
        "at most one course-over-ground update per interval"),
    real_param<NavigationConfig, &NavigationConfig::filter,
               &guidance::NavFilterParams::mag_cog_disagree_deg>(
        "filter.mag_cog_disagree_deg", "deg", 0.001, 180.0, kFixed,
        "mean course-over-ground minus magnetometer reported above this"),
    real_param<NavigationConfig, &NavigationConfig::filter,
               &guidance::NavFilterParams::mag_cog_window_s>(
        "filter.mag_cog_window_s", "s", 0.001, 600.0, kFixed, "time constant of that mean"),
    real_param<NavigationConfig, &NavigationConfig::filter,
               &guidance::NavFilterParams::gate_chi2_2dof>(
        "filter.gate_chi2_2dof", "", 0.001, 100.0, kFixed,
        "two-degree-of-freedom outlier gate (13.8 = 99.9 %)"),
    real_param<NavigationConfig, &NavigationConfig::filter,
               &guidance::NavFilterParams::gate_chi2_1dof>(
        "filter.gate_chi2_1dof", "", 0.001, 100.0, kFixed,
        "one-degree-of-freedom outlier gate (10.8 = 99.9 %)"),
    int_param<NavigationConfig, &NavigationConfig::filter,
              &guidance::NavFilterParams::max_rejected_fixes>(
        "filter.max_rejected_fixes", "", 0, 1000, kFixed,
        "consecutive refused fixes after which one is taken"),
    int_param<NavigationConfig, &NavigationConfig::filter,
              &guidance::NavFilterParams::max_rejected_headings>(
        "filter.max_rejected_headings", "", 0, 10000, kFixed, "the same for magnetometer samples"),
    real_param<NavigationConfig, &NavigationConfig::filter,
               &guidance::NavFilterParams::max_fix_gap_s>(
        "filter.max_fix_gap_s", "s", 0.001, 600.0, kFixed,
        "a longer GNSS outage restarts the position at the next fix"),
    real_param<NavigationConfig, &NavigationConfig::filter,
               &guidance::NavFilterParams::start_placement_sigma_m>(
        "filter.start_placement_sigma_m", "m", 0.001, 10.0, kFixed,
        "the boat on the known start point, per axis"),
    real_param<NavigationConfig, &NavigationConfig::filter,
               &guidance::NavFilterParams::uncalibrated_bias_sigma_m>(
        "filter.uncalibrated_bias_sigma_m", "m", 0.001, 50.0, kFixed,
        "no start calibration: receiver frame vs waypoints, per axis"),
};

constexpr std::array kCourse1{
    real_param<Course1Config, &Course1Config::turn_deg>(
        "turn_deg", "deg", -180.0, 180.0, kFixed,
        "turn after the first waypoint, relative to the heading there, + starboard"),
    real_param<Course1Config, &Course1Config::search_timeout_s>(
        "search_timeout_s", "s", 0.0, 600.0, kFixed, "then move on to course 2 anyway"),
    real_param<Course1Config, &Course1Config::search_thrust_frac>(
        "search_thrust_frac", "", 0.0, 1.0, kFixed, "thrust while turning"),
    enum_param<Course1Config, &Course1Config::buoy_colour>("buoy_colour", kColours, kFixed,
                                                           "colour of the buoy to look for"),
};

using guidance::BuoyCirclingParams;
constexpr std::array kCourse2{
    enum_param<Course2Config, &Course2Config::buoy_colour>("buoy_colour", kColours, kFixed,
                                                           "colour of the buoy to circle"),
    real_param<Course2Config, &Course2Config::circling, &BuoyCirclingParams::target_bearing_deg>(
        "target_bearing_deg", "deg", -360.0, 360.0, kFixed,
        "body bearing to hold the buoy at (- = port)"),
    real_param<Course2Config, &Course2Config::circling, &BuoyCirclingParams::target_distance_m>(
        "target_distance_m", "m", 0.1, 100.0, kFixed, "distance to hold from the buoy"),
    real_param<Course2Config, &Course2Config::circling, &BuoyCirclingParams::bearing_gain>(
        "bearing_gain", "", 1e-3, 100.0, kFixed, "desired turn per degree of bearing error"),
    real_param<Course2Config, &Course2Config::circling,
               &BuoyCirclingParams::distance_gain_deg_per_m>(
        "distance_gain_deg_per_m", "deg/m", 0.0, 1000.0, kFixed,
        "turn toward or away from the buoy per metre of distance error"),
    real_param<Course2Config, &Course2Config::circling,
               &BuoyCirclingParams::max_distance_correction_deg>(
        "max_distance_correction_deg", "deg", 0.0, 180.0, kFixed,
        "clamp of the distance correction"),
    real_param<Course2Config, &Course2Config::circling, &BuoyCirclingParams::max_turn_deg>(
        "max_turn_deg", "deg", 0.0, 180.0, kFixed, "clamp of the desired turn per step"),
    real_param<Course2Config, &Course2Config::circling, &BuoyCirclingParams::search_turn_deg>(
        "search_turn_deg", "deg", 0.0, 180.0, kFixed,
        "buoy not seen: keep turning this much to its side"),
    real_param<Course2Config, &Course2Config::circling, &BuoyCirclingParams::complete_turn_deg>(
        "complete_turn_deg", "deg", 1.0, 3600.0, kFixed, "accumulated turn that ends the circle"),
    real_param<Course2Config, &Course2Config::circling, &BuoyCirclingParams::max_heading_step_deg>(
        "max_heading_step_deg", "deg", -360.0, 360.0, kFixed,
        "a bigger heading jump between samples is a glitch, not a turn"),
    bool_param<Course2Config, &Course2Config::circling, &BuoyCirclingParams::count_only_seen>(
        "count_only_seen", kFixed,
        "only turns made with the buoy in sight count toward the circle (off: every turn)"),
    real_param<Course2Config, &Course2Config::circling_thrust_frac>(
        "circling_thrust_frac", "", 0.0, 1.0, kFixed, "thrust while circling"),
    real_param<Course2Config, &Course2Config::buoy_range_window_deg>(
        "buoy_range_window_deg", "deg", 0.0, 45.0, kFixed,
        "lidar bins either side of the camera bearing that range the buoy"),
    real_param<Course2Config, &Course2Config::buoy_memory_s>(
        "buoy_memory_s", "s", 0.0, 10.0, kFixed, "an older camera bearing is not steered on"),
    bool_param<Course2Config, &Course2Config::lidar_tracking>(
        "lidar_tracking", kFixed, "once seen, track the buoy with the lidar all the way round"),
    real_param<Course2Config, &Course2Config::buoy_radius_m>(
        "buoy_radius_m", "m", 0.0, 5.0, kFixed, "the buoy's radius (the lidar sees its near side)"),
    real_param<Course2Config, &Course2Config::track_gate_m>(
        "track_gate_m", "m", 1e-3, 100.0, kFixed,
        "a lidar obstacle this near the predicted buoy is the buoy"),
    real_param<Course2Config, &Course2Config::track_timeout_s>(
        "track_timeout_s", "s", 0.1, 60.0, kFixed,
        "unseen by the lidar this long: lost, search with the camera"),
    real_param<Course2Config, &Course2Config::exit_course_deg>(
        "exit_course_deg", "deg", -180.0, 180.0, kFixed,
        "course-frame heading held while looking for the colour"),
    real_param<Course2Config, &Course2Config::exit_align_deg>(
        "exit_align_deg", "deg", 1.0, 180.0, kFixed,
        "after the full turn, circle on until the heading is this near the exit course"),
    real_param<Course2Config, &Course2Config::seek_thrust_frac>(
        "seek_thrust_frac", "", 0.0, 1.0, kFixed, "thrust while looking for the colour"),
    real_param<Course2Config, &Course2Config::colour_timeout_s>(
        "colour_timeout_s", "s", 0.0, 3600.0, kFixed,
        "no colour by then: go on to the waypoint with the LED off"),
};

using guidance::DockingApproachParams;
using guidance::SlipFinderParams;
constexpr std::array kDocking{
    real_param<DockingConfig, &DockingConfig::approach, &DockingApproachParams::lookahead_m>(
        "lookahead_m", "m", 1e-3, 100.0, kFixed, "entry: aim this far ahead on the slip's axis"),
    real_param<DockingConfig, &DockingConfig::approach, &DockingApproachParams::stop_range_m>(
        "stop_range_m", "m", 1e-3, 100.0, kFixed, "range ahead below which the boat stops"),
    real_param<DockingConfig, &DockingConfig::approach, &DockingApproachParams::marker_gain>(
        "marker_gain", "", 0.0, 100.0, kFixed, "desired turn per degree of marker bearing"),
    real_param<DockingConfig, &DockingConfig::approach,
               &DockingApproachParams::max_marker_turn_deg>(
        "max_marker_turn_deg", "deg", 0.0, 180.0, kFixed, "clamp of one step's marker correction"),
    real_param<DockingConfig, &DockingConfig::approach,
               &DockingApproachParams::ahead_half_angle_deg>(
        "ahead_half_angle_deg", "deg", 0.5, 90.0, kFixed, "half-width of the range-ahead sector"),
    real_param<DockingConfig, &DockingConfig::decision_distance_m>(
        "decision_distance_m", "m", 1e-3, 100.0, kFixed,
        "2022: where the boat stops to look, before each slip"),
    real_param<DockingConfig, &DockingConfig::face_time_s>("face_time_s", "s", 0.1, 600.0, kFixed,
                                                           "2022: longest look at one slip"),
    real_param<DockingConfig, &DockingConfig::face_tolerance_deg>(
        "face_tolerance_deg", "deg", 0.5, 90.0, kFixed,
        "2022: votes count only when facing the slip within this"),
    real_param<DockingConfig, &DockingConfig::marker_window_deg>(
        "marker_window_deg", "deg", 0.5, 90.0, kFixed,
        "2022: only markers this near the bow are the slip's"),
    real_param<DockingConfig, &DockingConfig::approach_thrust_frac>(
        "approach_thrust_frac", "", 0.0, 1.0, kFixed, "thrust while entering"),
    real_param<DockingConfig, &DockingConfig::open_window_deg>(
        "open_window_deg", "deg", 0.0, 45.0, kFixed,
        "2026: a direction's range is the minimum over this either side"),
    real_param<DockingConfig, &DockingConfig::open_max_range_m>(
        "open_max_range_m", "m", 1e-3, 100.0, kFixed,
        "2026: ranges are capped here (no return = this far)"),
    real_param<DockingConfig, &DockingConfig::survey_distance_m>(
        "survey_distance_m", "m", 1e-3, 100.0, kFixed,
        "2022: look at every marker from this far before the slips"),
    real_param<DockingConfig, &DockingConfig::slip_depth_m>(
        "slip_depth_m", "m", 0.0, 20.0, kFixed,
        "2022: markers hang on the back wall this far inside"),
    real_param<DockingConfig, &DockingConfig::turn_thrust_frac>(
        "turn_thrust_frac", "", 0.0, 1.0, kFixed,
        "2022: thrust while turning to face a slip (no thrust, no rudder)"),
    real_param<DockingConfig, &DockingConfig::line_up_distance_m>(
        "line_up_distance_m", "m", 0.0, 50.0, kFixed,
        "2022: approach a decision point from this far behind it on the axis"),
    real_param<DockingConfig, &DockingConfig::axis_lookahead_m>(
        "axis_lookahead_m", "m", 1e-3, 100.0, kFixed,
        "2022: line of sight along a slip's axis toward its decision point"),
    real_param<DockingConfig, &DockingConfig::marker_fix_gain>(
        "marker_fix_gain", "", 0.0, 1.0, kFixed,
        "2022: weight of each frame's camera fix of the axis"),
    real_param<DockingConfig, &DockingConfig::marker_fix_max_range_m>(
        "marker_fix_max_range_m", "m", 1e-3, 100.0, kFixed,
        "2022: markers farther ahead do not fix the axis"),
    real_param<DockingConfig, &DockingConfig::max_marker_fix_m>(
        "max_marker_fix_m", "m", 0.0, 10.0, kFixed,
        "2022: largest sideways correction of the slip's axis"),
    real_param<DockingConfig, &DockingConfig::slip_match_m>(
        "slip_match_m", "m", 1e-3, 100.0, kFixed,
        "2022: a lidar mouth this near where the map puts the slip is that slip"),
    real_param<DockingConfig, &DockingConfig::commit_range_m>(
        "commit_range_m", "m", 1e-3, 100.0, kFixed,
        "2026: mouth nearer than this: hold the slip's axis"),
    real_param<DockingConfig, &DockingConfig::sweep_wall_range_m>(
        "sweep_wall_range_m", "m", 1e-3, 100.0, kFixed,
        "2026: far wall this near and no slip: sweep along it"),
    real_param<DockingConfig, &DockingConfig::sweep_standoff_m>(
        "sweep_standoff_m", "m", 1e-3, 100.0, kFixed,
        "2026: distance kept from the far wall while sweeping"),
    real_param<DockingConfig, &DockingConfig::sweep_turn_back_m>(
        "sweep_turn_back_m", "m", 1e-3, 100.0, kFixed,
        "2026: a side wall this near turns the sweep back"),
    real_param<DockingConfig, &DockingConfig::slip, &SlipFinderParams::min_width_m>(
        "slip_min_width_m", "m", 1e-3, 100.0, kFixed, "slip finder: narrower gaps do not fit"),
    real_param<DockingConfig, &DockingConfig::slip, &SlipFinderParams::max_width_m>(
        "slip_max_width_m", "m", 1e-3, 100.0, kFixed,
        "slip finder: wider gaps are open water, not a slip"),
    real_param<DockingConfig, &DockingConfig::slip, &SlipFinderParams::min_depth_m>(
        "slip_min_depth_m", "m", 1e-3, 100.0, kFixed,
        "slip finder: the inside reaches at least this beyond the tips"),
    real_param<DockingConfig, &DockingConfig::slip, &SlipFinderParams::max_depth_m>(
        "slip_max_depth_m", "m", 1e-3, 100.0, kFixed,
        "slip finder: and ends within this (a back wall)"),
    real_param<DockingConfig, &DockingConfig::slip, &SlipFinderParams::max_bearing_deg>(
        "slip_max_bearing_deg", "deg", 1.0, 180.0, kFixed,
        "slip finder: only mouths within this of the forward direction"),
    real_param<DockingConfig, &DockingConfig::slip, &SlipFinderParams::max_axis_deg>(
        "slip_max_axis_deg", "deg", 1.0, 180.0, kFixed,
        "slip finder: the slip's axis within this of the forward direction"),
    real_param<DockingConfig, &DockingConfig::slip, &SlipFinderParams::max_range_m>(
        "slip_max_range_m", "m", 1e-3, 100.0, kFixed, "slip finder: farther tips are ignored"),
    real_param<DockingConfig, &DockingConfig::stage_distance_m>(
        "stage_distance_m", "m", 1e-3, 100.0, kFixed,
        "2026: a slip seen off its axis, or missed, is approached again from this far out"),
    real_param<DockingConfig, &DockingConfig::turn_radius_m>(
        "turn_radius_m", "m", 0.1, 20.0, kFixed,
        "2026: the boat's turning circle at approach speed, to line up on a slip's axis"),
    real_param<DockingConfig, &DockingConfig::approach_funnel_deg>(
        "approach_funnel_deg", "deg", 0.0, 90.0, kFixed,
        "2026: straight in only from within this of the slip's axis, seen from its mouth"),
    real_param<DockingConfig, &DockingConfig::entry_tolerance_m>(
        "entry_tolerance_m", "m", 1e-3, 10.0, kFixed,
        "2026: at the commit range this near the slip's axis, or back off and line up again"),
    real_param<DockingConfig, &DockingConfig::entry_tolerance_deg>(
        "entry_tolerance_deg", "deg", 0.5, 90.0, kFixed,
        "2026: at the commit range the track along the axis within this, or back off"),
    real_param<DockingConfig, &DockingConfig::back_off_s>(
        "back_off_s", "s", 0.0, 60.0, kFixed,
        "2026: astern at most this long before lining up again"),
    real_param<DockingConfig, &DockingConfig::back_off_thrust_frac>(
        "back_off_thrust_frac", "", 0.0, 1.0, kFixed, "2026: thrust astern while backing off"),
    real_param<DockingConfig, &DockingConfig::finger_side_m>(
        "finger_side_m", "m", 1e-3, 10.0, kFixed,
        "2026: docked only when the lidar sees a finger this near each side"),
};

using guidance::GateParams;
using guidance::MapPlannerParams;
using guidance::NavMapParams;
using guidance::PlanningConfig;
using guidance::TurnSideParams;
constexpr std::array kPlanning{
    real_param<PlanningConfig, &PlanningConfig::map, &NavMapParams::resolution_m>(
        "map.resolution_m", "m", 0.05, 5.0, kFixed, "side of one map cell"),
    real_param<PlanningConfig, &PlanningConfig::map, &NavMapParams::margin_m>(
        "map.margin_m", "m", 0.0, 100.0, kFixed, "map margin around the field boundary"),
    real_param<PlanningConfig, &PlanningConfig::map, &NavMapParams::size_north_m>(
        "map.size_north_m", "m", 1.0, 1000.0, kFixed,
        "without a boundary: map extent north-south, centred on the origin"),
    real_param<PlanningConfig, &PlanningConfig::map, &NavMapParams::size_east_m>(
        "map.size_east_m", "m", 1.0, 1000.0, kFixed,
        "without a boundary: map extent east-west, centred on the origin"),
    real_param<PlanningConfig, &PlanningConfig::map, &NavMapParams::hit_log_odds>(
        "map.hit_log_odds", "", 0.01, 10.0, kFixed, "evidence added where a beam ends"),
    real_param<PlanningConfig, &PlanningConfig::map, &NavMapParams::miss_log_odds>(
        "map.miss_log_odds", "", -10.0, -0.01, kFixed,
        "evidence added to each cell a beam passes before its return"),
    real_param<PlanningConfig, &PlanningConfig::map, &NavMapParams::min_log_odds>(
        "map.min_log_odds", "", -50.0, -0.01, kFixed, "lower clamp of a cell's evidence"),
    real_param<PlanningConfig, &PlanningConfig::map, &NavMapParams::max_log_odds>(
        "map.max_log_odds", "", 0.01, 50.0, kFixed, "upper clamp of a cell's evidence"),
    real_param<PlanningConfig, &PlanningConfig::map, &NavMapParams::occupied_log_odds>(
        "map.occupied_log_odds", "", -50.0, 50.0, kFixed, "at or above: an obstacle"),
    real_param<PlanningConfig, &PlanningConfig::map, &NavMapParams::max_range_m>(
        "map.max_range_m", "m", 0.5, 100.0, kFixed, "beams clear and mark only this far"),
    real_param<PlanningConfig, &PlanningConfig::map, &NavMapParams::min_range_m>(
        "map.min_range_m", "m", 0.0, 10.0, kFixed, "nearer returns are the hull or spray"),
    bool_param<PlanningConfig, &PlanningConfig::map, &NavMapParams::no_return_clears>(
        "map.no_return_clears", kFixed,
        "a beam with no return clears its whole length (open water reflects nothing)"),
    real_param<PlanningConfig, &PlanningConfig::map, &NavMapParams::no_return_near_m>(
        "map.no_return_near_m", "m", 0.0, 5.0, kFixed,
        "a scan with a return nearer than this clears nothing along its beams without one (a "
        "wall inside the scanner's least range returns nothing too); 0: always clears"),
    bool_param<PlanningConfig, &PlanningConfig::planner, &MapPlannerParams::enabled>(
        "planner.enabled", kFixed,
        "plan a global path on the map; the reactive avoidance steers to its sub-goal"),
    real_param<PlanningConfig, &PlanningConfig::planner, &MapPlannerParams::replan_period_s>(
        "planner.replan_period_s", "s", 0.02, 10.0, kFixed, "replan at most this often"),
    real_param<PlanningConfig, &PlanningConfig::planner, &MapPlannerParams::clearance_m>(
        "planner.clearance_m", "m", 0.0, 3.0, kFixed,
        "obstacles are inflated by the avoidance's half beam plus this"),
    real_param<PlanningConfig, &PlanningConfig::planner, &MapPlannerParams::soft_clearance_m>(
        "planner.soft_clearance_m", "m", 0.0, 10.0, kFixed,
        "beyond the inflation, a band this wide where a path pays to come near an obstacle"),
    real_param<PlanningConfig, &PlanningConfig::planner, &MapPlannerParams::clearance_cost>(
        "planner.clearance_cost", "", 0.0, 15.0, kFixed,
        "extra cost per metre at the inflation's edge, falling off as a square across the band"),
    real_param<PlanningConfig, &PlanningConfig::planner, &MapPlannerParams::unknown_cost>(
        "planner.unknown_cost", "", 0.0, 15.0, kFixed,
        "extra cost per metre of water the lidar has never seen"),
    real_param<PlanningConfig, &PlanningConfig::planner, &MapPlannerParams::goal_fade_m>(
        "planner.goal_fade_m", "m", 0.0, 50.0, kFixed,
        "within this of the goal the clearance and unknown costs fade out toward it"),
    real_param<PlanningConfig, &PlanningConfig::planner, &MapPlannerParams::sight_full_speed_m>(
        "planner.sight_full_speed_m", "m", 0.0, 100.0, kFixed,
        "full speed only while the path ahead runs this far through water the lidar has seen "
        "(0: no limit)"),
    real_param<PlanningConfig, &PlanningConfig::planner, &MapPlannerParams::sight_min_speed_factor>(
        "planner.sight_min_speed_factor", "", 0.01, 1.0, kFixed,
        "speed factor with the unseen right ahead (it rises in proportion to the seen run)"),
    real_param<PlanningConfig, &PlanningConfig::planner, &MapPlannerParams::turn_slow_deg>(
        "planner.turn_slow_deg", "deg", 0.0, 89.0, kFixed,
        "the path's sub-goal more than this off the bow: slower for the turn (0: off)"),
    real_param<PlanningConfig, &PlanningConfig::planner, &MapPlannerParams::turn_min_speed_factor>(
        "planner.turn_min_speed_factor", "", 0.01, 1.0, kFixed,
        "speed factor with the sub-goal 90 deg or more off the bow"),
    real_param<PlanningConfig, &PlanningConfig::planner, &MapPlannerParams::lookahead_m>(
        "planner.lookahead_m", "m", 0.1, 50.0, kFixed, "the sub-goal's distance along the path"),
    real_param<PlanningConfig, &PlanningConfig::planner, &MapPlannerParams::line_of_sight_min_m>(
        "planner.line_of_sight_min_m", "m", 0.0, 50.0, kFixed,
        "the sub-goal comes nearer, down to this, until the boat can steer straight at it"),
    int_param<PlanningConfig, &PlanningConfig::planner, &MapPlannerParams::max_expansions>(
        "planner.max_expansions", "", 1, 1 << 20, kFixed, "A* expansion budget per plan"),
    real_param<PlanningConfig, &PlanningConfig::planner, &MapPlannerParams::heuristic_weight>(
        "planner.heuristic_weight", "", 1.0, 5.0, kFixed,
        "weighted A*: a path at most this many times the cheapest one's cost, found faster "
        "(1: the cheapest)"),
    real_param<PlanningConfig, &PlanningConfig::planner, &MapPlannerParams::goal_search_m>(
        "planner.goal_search_m", "m", 0.0, 5.0, kFixed,
        "a blocked goal moves to the nearest free cell this near"),
    real_param<PlanningConfig, &PlanningConfig::planner, &MapPlannerParams::stop_s>(
        "planner.stop_s", "s", 0.0, 60.0, kFixed, "no path: stop this long"),
    real_param<PlanningConfig, &PlanningConfig::planner, &MapPlannerParams::back_off_s>(
        "planner.back_off_s", "s", 0.0, 60.0, kFixed, "no path: then back off this long"),
    real_param<PlanningConfig, &PlanningConfig::planner, &MapPlannerParams::back_off_thrust_frac>(
        "planner.back_off_thrust_frac", "", 0.0, 1.0, kFixed, "astern thrust while backing off"),
    real_param<PlanningConfig, &PlanningConfig::planner, &MapPlannerParams::look_s>(
        "planner.look_s", "s", 0.0, 60.0, kFixed, "no path: then turn to look this long"),
    real_param<PlanningConfig, &PlanningConfig::planner, &MapPlannerParams::look_turn_deg>(
        "planner.look_turn_deg", "deg", -180.0, 180.0, kFixed,
        "the look turn, relative to the goal's bearing"),
    real_param<PlanningConfig, &PlanningConfig::planner, &MapPlannerParams::look_thrust_frac>(
        "planner.look_thrust_frac", "", 0.0, 1.0, kFixed, "thrust while turning to look"),
    real_param<PlanningConfig, &PlanningConfig::planner, &MapPlannerParams::stuck_s>(
        "planner.stuck_s", "s", 0.0, 600.0, kFixed,
        "stuck (with or without the planner): no progress this long starts stop, back off, "
        "turn to the path; 0 never"),
    real_param<PlanningConfig, &PlanningConfig::planner, &MapPlannerParams::stuck_distance_m>(
        "planner.stuck_distance_m", "m", 0.01, 20.0, kFixed,
        "progress: moving this far from where the boat was"),
    bool_param<PlanningConfig, &PlanningConfig::planner, &MapPlannerParams::astern_enabled>(
        "planner.astern_enabled", kFixed,
        "back along the path, stern first, when its sub-goal is behind and the turn has no room"),
    real_param<PlanningConfig, &PlanningConfig::planner, &MapPlannerParams::astern_behind_deg>(
        "planner.astern_behind_deg", "deg", 90.0, 180.0, kFixed,
        "the sub-goal counts as behind this far off the bow"),
    real_param<PlanningConfig, &PlanningConfig::planner, &MapPlannerParams::astern_thrust_frac>(
        "planner.astern_thrust_frac", "", 0.0, 1.0, kFixed, "astern thrust along the path"),
    real_param<PlanningConfig, &PlanningConfig::planner, &MapPlannerParams::astern_look_m>(
        "planner.astern_look_m", "m", 0.0, 5.0, kFixed,
        "astern only while this much water behind the stern is clear"),
    real_param<PlanningConfig, &PlanningConfig::planner, &MapPlannerParams::astern_max_m>(
        "planner.astern_max_m", "m", 0.0, 50.0, kFixed, "at most this far astern at a time"),
    bool_param<PlanningConfig, &PlanningConfig::gates, &GateParams::judge_by_lidar>(
        "gates.judge_by_lidar", kFixed,
        "a gate is passed when the track crosses between its buoys as the lidar places them"),
    real_param<PlanningConfig, &PlanningConfig::gates, &GateParams::width_m>(
        "gates.width_m", "m", 0.1, 50.0, kFixed, "gate width, buoy centre to buoy centre"),
    real_param<PlanningConfig, &PlanningConfig::gates, &GateParams::width_tolerance_m>(
        "gates.width_tolerance_m", "m", 0.0, 10.0, kFixed, "accepted error of the width"),
    real_param<PlanningConfig, &PlanningConfig::gates, &GateParams::search_radius_m>(
        "gates.search_radius_m", "m", 0.1, 50.0, kFixed,
        "a buoy pair's midpoint this near the waypoint is its gate"),
    real_param<PlanningConfig, &PlanningConfig::gates, &GateParams::max_angle_deg>(
        "gates.max_angle_deg", "deg", 0.0, 90.0, kFixed,
        "the pair's line this near square to the leg"),
    real_param<PlanningConfig, &PlanningConfig::gates, &GateParams::max_buoy_length_m>(
        "gates.max_buoy_length_m", "m", 0.01, 10.0, kFixed, "longer segments are not buoys"),
    real_param<PlanningConfig, &PlanningConfig::gates, &GateParams::track_gate_m>(
        "gates.track_gate_m", "m", 0.01, 10.0, kFixed,
        "a sighting this near the tracked gate updates it"),
    real_param<PlanningConfig, &PlanningConfig::gates, &GateParams::approach_m>(
        "gates.approach_m", "m", 0.1, 50.0, kFixed,
        "after a miss, go back to this far before the gate"),
    real_param<PlanningConfig, &PlanningConfig::gates, &GateParams::wall_m>(
        "gates.wall_m", "m", 0.0, 100.0, kFixed,
        "while a gate is the goal, its line this far beyond each end is a wall to the planner "
        "(0: off)"),
    bool_param<PlanningConfig, &PlanningConfig::turn_side, &TurnSideParams::enabled>(
        "turn_side.enabled", kFixed,
        "waypoint-only tasks (hopping): a large turn goes the long way round when the lidar sees "
        "the short way's turning circle blocked"),
    real_param<PlanningConfig, &PlanningConfig::turn_side, &TurnSideParams::min_turn_deg>(
        "turn_side.min_turn_deg", "deg", 0.0, 180.0, kFixed,
        "smaller changes of heading always turn the short way"),
    real_param<PlanningConfig, &PlanningConfig::turn_side, &TurnSideParams::clearance_m>(
        "turn_side.clearance_m", "m", 0.0, 10.0, kFixed,
        "room kept between the swept hull of the turn and what the lidar sees"),
    real_param<PlanningConfig, &PlanningConfig::turn_side, &TurnSideParams::release_deg>(
        "turn_side.release_deg", "deg", 0.01, 90.0, kFixed,
        "a side taken is held until the heading is this near the desired one"),
    real_param<PlanningConfig, &PlanningConfig::turn_side, &TurnSideParams::turn_radius_m>(
        "turn_side.turn_radius_m", "m", 0.01, 50.0, kFixed,
        "the pivot's turning circle at sailing speed, drift included"),
};

// ---- boat ---------------------------------------------------------------------------------

constexpr std::array kLayouts{
    ParamChoice{"servo_thruster", static_cast<int>(msg::ActuatorLayout::kServoThruster)},
    ParamChoice{"twin_thrusters", static_cast<int>(msg::ActuatorLayout::kTwinThrusters)},
};
using core::MountTransform;
template <MountTransform MountsConfig::*Mount>
constexpr std::array<ParamSpec<BoatConfig>, 3> mount_rows(std::string_view yaw, std::string_view x,
                                                          std::string_view y) {
  return {real_param<BoatConfig, &BoatConfig::mounts, Mount, &MountTransform::yaw_deg>(
              yaw, "deg", -360.0, 360.0, kFixed, "sensor's yaw in the body frame"),
          real_param<BoatConfig, &BoatConfig::mounts, Mount, &MountTransform::x_m>(
              x, "m", -10.0, 10.0, kFixed, "sensor position, forward of the body origin"),
          real_param<BoatConfig, &BoatConfig::mounts, Mount, &MountTransform::y_m>(
              y, "m", -10.0, 10.0, kFixed, "sensor position, starboard of the body origin")};
}
constexpr auto kLidarMount = mount_rows<&MountsConfig::lidar>(
    "mounts.lidar.yaw_deg", "mounts.lidar.x_m", "mounts.lidar.y_m");
constexpr auto kImuMount =
    mount_rows<&MountsConfig::imu>("mounts.imu.yaw_deg", "mounts.imu.x_m", "mounts.imu.y_m");
constexpr auto kGnssMount =
    mount_rows<&MountsConfig::gnss>("mounts.gnss.yaw_deg", "mounts.gnss.x_m", "mounts.gnss.y_m");
constexpr auto kCameraMount = mount_rows<&MountsConfig::camera>(
    "mounts.camera.yaw_deg", "mounts.camera.x_m", "mounts.camera.y_m");

using A = ActuatorsConfig;
constexpr std::array kBoat{
    text_param<BoatConfig, &BoatConfig::name>("name", "free text, shown in logs and reports"),
    real_param<BoatConfig, &BoatConfig::hull, &HullConfig::length_m>(
        "hull.length_m", "m", 0.2, 20.0, kFixed, "overall length"),
    real_param<BoatConfig, &BoatConfig::hull, &HullConfig::beam_m>("hull.beam_m", "m", 0.1, 10.0,
                                                                   kFixed, "overall width"),
    real_param<BoatConfig, &BoatConfig::hull, &HullConfig::bow_overhang_m>(
        "hull.bow_overhang_m", "m", 0.0, 20.0, kFixed, "body origin to the tip of the bow"),
    kLidarMount[0],
    kLidarMount[1],
    kLidarMount[2],
    kImuMount[0],
    kImuMount[1],
    kImuMount[2],
    kGnssMount[0],
    kGnssMount[1],
    kGnssMount[2],
    kCameraMount[0],
    kCameraMount[1],
    kCameraMount[2],
    enum_param<BoatConfig, &BoatConfig::actuators, &A::layout>(
        "actuators.layout", kLayouts, kFixed,
        "one stern thruster turned by a servo, or two fixed thrusters"),
    real_param<BoatConfig, &BoatConfig::actuators, &A::command_rate_hz>(
        "actuators.command_rate_hz", "Hz", 1.0, 200.0, kFixed,
        "how often commands go to the Arduino"),
    real_param<BoatConfig, &BoatConfig::actuators, &A::twin_track_width_m>(
        "actuators.twin_track_width_m", "m", 0.05, 10.0, kFixed,
        "distance between the twin thrusters"),
    int_param<BoatConfig, &BoatConfig::actuators, &A::servo, &ServoConfig::center_us>(
        "actuators.servo.center_us", "us", 500, 2500, kFixed, "servo pulse for straight ahead"),
    int_param<BoatConfig, &BoatConfig::actuators, &A::servo, &ServoConfig::min_us>(
        "actuators.servo.min_us", "us", 500, 2500, kFixed, "shortest servo pulse"),
    int_param<BoatConfig, &BoatConfig::actuators, &A::servo, &ServoConfig::max_us>(
        "actuators.servo.max_us", "us", 500, 2500, kFixed, "longest servo pulse"),
    real_param<BoatConfig, &BoatConfig::actuators, &A::servo, &ServoConfig::max_deflection_deg>(
        "actuators.servo.max_deflection_deg", "deg", 1.0, 90.0, kFixed,
        "deflection at min_us and max_us"),
    real_param<BoatConfig, &BoatConfig::actuators, &A::servo, &ServoConfig::rate_deg_per_s>(
        "actuators.servo.rate_deg_per_s", "deg/s", 1.0, 5000.0, kFixed, "servo slew rate"),
    int_param<BoatConfig, &BoatConfig::actuators, &A::servo, &ServoConfig::deadband_us>(
        "actuators.servo.deadband_us", "us", 0, 100, kFixed, "servo deadband"),
    bool_param<BoatConfig, &BoatConfig::actuators, &A::servo, &ServoConfig::reversed>(
        "actuators.servo.reversed", kFixed, "a larger pulse turns the bow to port"),
    int_param<BoatConfig, &BoatConfig::actuators, &A::thruster, &ThrusterConfig::neutral_us>(
        "actuators.thruster.neutral_us", "us", 500, 2500, kFixed, "ESC pulse for no thrust"),
    int_param<BoatConfig, &BoatConfig::actuators, &A::thruster, &ThrusterConfig::min_us>(
        "actuators.thruster.min_us", "us", 500, 2500, kFixed, "full reverse"),
    int_param<BoatConfig, &BoatConfig::actuators, &A::thruster, &ThrusterConfig::max_us>(
        "actuators.thruster.max_us", "us", 500, 2500, kFixed, "full forward"),
    int_param<BoatConfig, &BoatConfig::actuators, &A::thruster, &ThrusterConfig::forward_start_us>(
        "actuators.thruster.forward_start_us", "us", 500, 2500, kFixed,
        "forward thrust starts above this"),
    int_param<BoatConfig, &BoatConfig::actuators, &A::thruster, &ThrusterConfig::reverse_start_us>(
        "actuators.thruster.reverse_start_us", "us", 500, 2500, kFixed,
        "reverse thrust starts below this"),
    bool_param<BoatConfig, &BoatConfig::actuators, &A::thruster, &ThrusterConfig::reverse_allowed>(
        "actuators.thruster.reverse_allowed", kFixed, "the ESC may be driven astern"),
};

// ---- devices ------------------------------------------------------------------------------

template <class D>
constexpr std::array<ParamSpec<D>, 4> serial_rows() {
  return {bool_param<D, &SerialDeviceConfig::enabled>("enabled", kFixed, "use this device"),
          text_param<D, &SerialDeviceConfig::path>("path", "serial device path"),
          int_param<D, &SerialDeviceConfig::baud>("baud", "bit/s", 1200, 4'000'000, kFixed,
                                                  "serial baud rate"),
          int_param<D, &SerialDeviceConfig::timeout_ms>("timeout_ms", "ms", 20, 60'000, kFixed,
                                                        "silence longer than this = unhealthy")};
}

constexpr std::array kScanModes{
    ParamChoice{"auto", static_cast<int>(LidarScanMode::kAuto)},
    ParamChoice{"standard", static_cast<int>(LidarScanMode::kStandard)},
    ParamChoice{"express", static_cast<int>(LidarScanMode::kExpress)},
};
constexpr auto kLidarSerial = serial_rows<LidarDeviceConfig>();
constexpr std::array kLidar{
    kLidarSerial[0],
    kLidarSerial[1],
    kLidarSerial[2],
    kLidarSerial[3],
    enum_param<LidarDeviceConfig, &LidarDeviceConfig::scan_mode>(
        "scan_mode", kScanModes, kFixed, "auto picks the densest mode the model supports"),
    int_param<LidarDeviceConfig, &LidarDeviceConfig::motor_pwm>("motor_pwm", "", 0, 1023, kFixed,
                                                                "A2/A3 accessory board motor PWM"),
    int_param<LidarDeviceConfig, &LidarDeviceConfig::motor_rpm>("motor_rpm", "rpm", 0, 3000, kFixed,
                                                                "S-series motor speed"),
};

constexpr std::array kImuOutputs{
    ParamChoice{"ascii", static_cast<int>(ImuOutput::kAscii)},
    ParamChoice{"binary", static_cast<int>(ImuOutput::kBinary)},
};
constexpr auto kImuSerial = serial_rows<ImuDeviceConfig>();
constexpr std::array kImu{
    kImuSerial[0],
    kImuSerial[1],
    kImuSerial[2],
    kImuSerial[3],
    enum_param<ImuDeviceConfig, &ImuDeviceConfig::output>("output", kImuOutputs, kFixed,
                                                          "the myAHRS+ output format"),
    real_param<ImuDeviceConfig, &ImuDeviceConfig::rate_hz>("rate_hz", "Hz", 1.0, 100.0, kFixed,
                                                           "output rate"),
    real_param<ImuDeviceConfig, &ImuDeviceConfig::declination_deg>(
        "declination_deg", "deg", -180.0, 180.0, kFixed,
        "magnetic declination at the site, east positive"),
    real_param<ImuDeviceConfig, &ImuDeviceConfig::mag_hard_iron_x_ut>(
        "mag_hard_iron_x_ut", "uT", -1000.0, 1000.0, kFixed,
        "magnetometer hard iron, board x (coxswain calibrate mag)"),
    real_param<ImuDeviceConfig, &ImuDeviceConfig::mag_hard_iron_y_ut>(
        "mag_hard_iron_y_ut", "uT", -1000.0, 1000.0, kFixed,
        "magnetometer hard iron, board y (coxswain calibrate mag)"),
    real_param<ImuDeviceConfig, &ImuDeviceConfig::mag_soft_iron_xx>(
        "mag_soft_iron_xx", "", -10.0, 10.0, kFixed, "magnetometer soft-iron map, row 1 column 1"),
    real_param<ImuDeviceConfig, &ImuDeviceConfig::mag_soft_iron_xy>(
        "mag_soft_iron_xy", "", -10.0, 10.0, kFixed, "magnetometer soft-iron map, row 1 column 2"),
    real_param<ImuDeviceConfig, &ImuDeviceConfig::mag_soft_iron_yx>(
        "mag_soft_iron_yx", "", -10.0, 10.0, kFixed, "magnetometer soft-iron map, row 2 column 1"),
    real_param<ImuDeviceConfig, &ImuDeviceConfig::mag_soft_iron_yy>(
        "mag_soft_iron_yy", "", -10.0, 10.0, kFixed, "magnetometer soft-iron map, row 2 column 2"),
};

constexpr std::array kReceivers{
    ParamChoice{"f9", static_cast<int>(GnssReceiver::kF9)},
    ParamChoice{"m8", static_cast<int>(GnssReceiver::kM8)},
};
constexpr std::array kPorts{
    ParamChoice{"usb", static_cast<int>(GnssPort::kUsb)},
    ParamChoice{"uart1", static_cast<int>(GnssPort::kUart1)},
};
constexpr auto kGnssSerial = serial_rows<GnssDeviceConfig>();
constexpr std::array kGnss{
    kGnssSerial[0],
    kGnssSerial[1],
    kGnssSerial[2],
    kGnssSerial[3],
    enum_param<GnssDeviceConfig, &GnssDeviceConfig::receiver>(
        "receiver", kReceivers, kFixed, "receiver generation (configuration messages differ)"),
    enum_param<GnssDeviceConfig, &GnssDeviceConfig::port>("port", kPorts, kFixed,
                                                          "receiver port the cable is on"),
    real_param<GnssDeviceConfig, &GnssDeviceConfig::rate_hz>("rate_hz", "Hz", 0.1, 25.0, kFixed,
                                                             "navigation rate"),
    bool_param<GnssDeviceConfig, &GnssDeviceConfig::nmea_output>("nmea_output", kFixed,
                                                                 "keep NMEA output on beside UBX"),
    text_param<GnssDeviceConfig, &GnssDeviceConfig::rtcm_input>(
        "rtcm_input", "RTK corrections: \"\", a file or pipe path, or tcp://host:port"),
};

constexpr auto kArduinoSerial = serial_rows<ArduinoDeviceConfig>();
constexpr std::array kArduino{
    kArduinoSerial[0],
    kArduinoSerial[1],
    kArduinoSerial[2],
    kArduinoSerial[3],
    int_param<ArduinoDeviceConfig, &ArduinoDeviceConfig::failsafe_ms>(
        "failsafe_ms", "ms", 50, 5000, kFixed,
        "the firmware goes neutral when no command arrives for this long"),
};

using C = CameraDeviceConfig;
constexpr std::array kCamera{
    bool_param<C, &C::enabled>("enabled", kFixed, "use the camera"),
    text_param<C, &C::source>("source", "a V4L2 device, a video file or an image directory"),
    bool_param<C, &C::loop>("loop", kFixed,
                            "video file or image directory: start again at the end"),
    int_param<C, &C::width_px>("width_px", "px", 16, 8192, kFixed, "frame width"),
    int_param<C, &C::height_px>("height_px", "px", 16, 8192, kFixed, "frame height"),
    real_param<C, &C::fps>("fps", "Hz", 0.5, 240.0, kFixed, "frame rate"),
    real_param<C, &C::hfov_deg>("hfov_deg", "deg", 5.0, 179.0, kFixed, "horizontal field of view"),
    bool_param<C, &C::auto_exposure>("auto_exposure", kFixed, "let the camera set exposure"),
    real_param<C, &C::exposure>("exposure", "", 0.0, kBig, kFixed, "V4L2 exposure"),
    real_param<C, &C::saturation>("saturation", "", 0.0, kBig, kFixed, "V4L2 saturation"),
    real_param<C, &C::contrast>("contrast", "", 0.0, kBig, kFixed, "V4L2 contrast"),
    real_param<C, &C::brightness>("brightness", "", 0.0, kBig, kFixed, "V4L2 brightness"),
    int_param<C, &C::timeout_ms>("timeout_ms", "ms", 20, 60'000, kFixed,
                                 "no frame for this long = unhealthy"),
    real_param<C, &C::image_rate_hz>(
        "image_rate_hz", "Hz", 0.0, 30.0, kFixed,
        "JPEG frames for the recording and the live view (/camera/image) at most this often; "
        "0 = none"),
    int_param<C, &C::image_max_width_px>("image_max_width_px", "px", 16, 8192, kFixed,
                                         "those frames scaled down to at most this width"),
    int_param<C, &C::image_jpeg_quality>("image_jpeg_quality", "", 1, 100, kFixed,
                                         "their JPEG quality (higher: sharper, larger)"),
};

constexpr std::array kLiveServer{
    text_param<LiveConfig, &LiveConfig::control_socket>(
        "control_socket", "control socket path; \"\" = <run directory>/control.sock"),
    bool_param<LiveConfig, &LiveConfig::http_enabled>(
        "http_enabled", kFixed, "serve the status page and the Foxglove WebSocket"),
    text_param<LiveConfig, &LiveConfig::http_address>("http_address",
                                                      "address the live server listens on"),
    int_param<LiveConfig, &LiveConfig::http_port>("http_port", "", 0, 65535, kFixed,
                                                  "port of the live server; 0 = any free port"),
    real_param<LiveConfig, &LiveConfig::viz_rate_hz>(
        "viz_rate_hz", "Hz", 0.1, 100.0, kFixed,
        "Foxglove messages per channel at most this often"),
    core::secret_param<LiveConfig, &LiveConfig::token>(
        "token", "needed by every state-changing request; \"\" = control disabled"),
    core::text_list_param<LiveConfig, &LiveConfig::allowed_hosts>(
        "allowed_hosts",
        "host names besides IP literals and localhost that name this server (e.g. boat.local)"),
    core::text_list_param<LiveConfig, &LiveConfig::allowed_origins>(
        "allowed_origins", "browser origins (scheme://host[:port]) besides the server's own"),
};

}  // namespace

template <>
std::span<const ParamSpec<control::HeadingPidParams>> param_table() {
  return kHeadingPid;
}
template <>
std::span<const ParamSpec<control::SpeedScheduleParams>> param_table() {
  return kSpeed;
}
template <>
std::span<const ParamSpec<guidance::AvoidanceParams>> param_table() {
  return kAvoidance;
}
template <>
std::span<const ParamSpec<guidance::WaypointFollowerParams>> param_table() {
  return kWaypoints;
}
template <>
std::span<const ParamSpec<guidance::GpsCalibrationParams>> param_table() {
  return kGpsCalibration;
}
template <>
std::span<const ParamSpec<perception::LidarClusterParams>> param_table() {
  return kClustering;
}
template <>
std::span<const ParamSpec<perception::MarkerVoteParams>> param_table() {
  return kVisionVote;
}
template <>
std::span<const ParamSpec<perception::VisionParams>> param_table() {
  return kVision;
}
template <>
std::span<const ParamSpec<perception::ColourRange>> param_table() {
  return kColourRange;
}
template <>
std::span<const ParamSpec<MissionConfig>> param_table() {
  return kMission;
}
template <>
std::span<const ParamSpec<NavigationConfig>> param_table() {
  return kNavigation;
}
template <>
std::span<const ParamSpec<Course1Config>> param_table() {
  return kCourse1;
}
template <>
std::span<const ParamSpec<Course2Config>> param_table() {
  return kCourse2;
}
template <>
std::span<const ParamSpec<DockingConfig>> param_table() {
  return kDocking;
}
template <>
std::span<const ParamSpec<guidance::PlanningConfig>> param_table() {
  return kPlanning;
}
template <>
std::span<const ParamSpec<BoatConfig>> param_table() {
  return kBoat;
}
template <>
std::span<const ParamSpec<LidarDeviceConfig>> param_table() {
  return kLidar;
}
template <>
std::span<const ParamSpec<ImuDeviceConfig>> param_table() {
  return kImu;
}
template <>
std::span<const ParamSpec<GnssDeviceConfig>> param_table() {
  return kGnss;
}
template <>
std::span<const ParamSpec<ArduinoDeviceConfig>> param_table() {
  return kArduino;
}
template <>
std::span<const ParamSpec<CameraDeviceConfig>> param_table() {
  return kCamera;
}
template <>
std::span<const ParamSpec<LiveConfig>> param_table() {
  return kLiveServer;
}

std::span<const ParamChoice> colour_choices() { return kColours; }

std::string_view task_type_name(TaskType type) {
  switch (type) {
    case TaskType::kHopping:
      return "hopping";
    case TaskType::kObstacleCourse:
      return "obstacle_course";
    case TaskType::kCourse1:
      return "course1";
    case TaskType::kCourse2:
      return "course2";
    case TaskType::kDocking:
      return "docking";
  }
  return "unknown";
}

}  // namespace coxswain::config
