// SPDX-License-Identifier: Apache-2.0
#pragma once
// Internal to the mission core: the task level of the state machine. Each task owns its engines
// and phases; the core owns the safety layer above it, the navigation estimate, perception and
// the control pipeline below it. Not thread-safe; no allocation after construction.
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string_view>

#include "coxswain/config/config.hpp"
#include "coxswain/core/frames.hpp"
#include "coxswain/core/geodesy.hpp"
#include "coxswain/core/time.hpp"
#include "coxswain/guidance/avoidance.hpp"
#include "coxswain/guidance/nav_filter.hpp"
#include "coxswain/guidance/nav_map.hpp"
#include "coxswain/mission/mission_core.hpp"
#include "coxswain/msg/camera_detections.hpp"
#include "coxswain/perception/obstacles.hpp"

namespace coxswain::mission::detail {

/// Sensors a task needs; losing one mid-task puts the boat in hold.
enum Need : std::uint8_t {
  kNeedGnss = 1U << 0U,
  kNeedImu = 1U << 1U,
  kNeedLidar = 1U << 2U,
};

/// A plan a task asks for on one tick. The core makes it after that tick's commands are out
/// (MissionCore::finish_tick, at the latest as the next step begins), so no tick waits for A*;
/// the task takes the result on a later tick.
struct PlanRequest {
  bool pending = false;
  const void* owner = nullptr;  // the task that asked
  core::NavPoint start;
  core::NavPoint goal;
  /// Lines the path may not cross (a gate's line beyond its ends), the first wall_count.
  std::array<guidance::PlanWall, 2> walls{};
  std::size_t wall_count = 0;
  /// Plans made so far, the task the last one was made for, and its outcome.
  std::uint64_t made = 0;
  const void* made_for = nullptr;
  guidance::PlanStatus status = guidance::PlanStatus::kNoPath;
};

/// What the core knows this tick, handed to the task.
struct TaskContext {
  core::TimeNs now_ns = 0;
  bool position_valid = false;  // usable, fresh, GPS-offset-corrected fix
  bool heading_valid = false;
  core::NavPose pose;      // body origin (bow)
  core::NavPoint antenna;  // GPS antenna (mid-length): what waypoint arrival is judged on
  /// The estimator's covariance of `antenna` (the body origin's differs by the heading's share
  /// through the lever arm, which is small). Invalid with the documents' raw fixes. Use
  /// guidance::confidently_within / confident_crossing to judge a point or a line by it.
  bool position_cov_valid = false;
  guidance::PositionCovariance position_cov;
  bool lidar_fresh = false;
  bool lidar_new = false;  // a scan arrived this tick
  const perception::ObstacleList* obstacles = nullptr;
  const perception::RangeProfile* profile = nullptr;
  bool camera_fresh = false;
  bool camera_new = false;  // a frame arrived this tick
  const msg::CameraDetections* camera = nullptr;
  /// The mission's map and planner (null when no task plans), as the work after the last tick
  /// left them: this tick's scan joins the map, and a plan asked for now is made, after this
  /// tick (see PlanRequest).
  const guidance::NavMap* map = nullptr;
  const guidance::MapPlanner* planner = nullptr;
  PlanRequest* plan = nullptr;
  msg::Colour target_colour = msg::Colour::kUnknown;  // operator input, else the task's
  msg::Shape target_shape = msg::Shape::kUnknown;
  double course_zero_deg = 0.0;
  double task_elapsed_s = 0.0;
  VizFrame* viz = nullptr;
  MissionStatus* status = nullptr;
};

/// What the task asks of the control pipeline.
struct GuidanceRequest {
  bool steer = false;  // false: neutral outputs (stop)
  double desired_heading_deg = 0.0;
  /// Thrust setpoint: from the speed schedule by distance when set, else `thrust_frac`.
  std::optional<double> schedule_distance_m;
  double thrust_frac = 0.0;
  double speed_factor = 1.0;  // multiplies the setpoint (avoidance slows down, negative astern)
  std::optional<msg::LedColour> led;  // set the LED (kept until changed)
};

enum class TaskResult : std::uint8_t { kRunning = 0, kDone, kFailed };

/// One task. enter() returns a refusal reason (empty = entered); step() runs one tick; a phase
/// change is reported by set_phase(), which the core turns into a logged transition.
class Task {
 public:
  virtual ~Task() = default;
  [[nodiscard]] std::string_view name() const { return name_.view(); }
  [[nodiscard]] std::string_view phase() const { return phase_.view(); }
  [[nodiscard]] virtual std::uint8_t needs() const = 0;
  /// Empty = entered; else why not (the core retries every tick).
  virtual ReasonText enter(const TaskContext& ctx) = 0;
  virtual TaskResult step(const TaskContext& ctx, GuidanceRequest& out) = 0;
  virtual void exit() {}
  /// New avoidance parameters (live retuning, between two steps; validated). Tasks with an
  /// avoidance engine rebuild it; the others ignore them.
  virtual void retune_avoidance(const guidance::AvoidanceParams& params) { (void)params; }

  /// Set by step() when it returns kDone/kFailed, or when it changes phase.
  [[nodiscard]] const ReasonText& reason() const { return reason_; }
  /// True once after a phase change (read and cleared by the core).
  bool take_phase_change() {
    const bool c = phase_changed_;
    phase_changed_ = false;
    return c;
  }

 protected:
  explicit Task(std::string_view name) { name_.assign(name); }
  void set_phase(std::string_view phase, std::string_view reason) {
    phase_.assign(phase);
    reason_.assign(reason);
    phase_changed_ = true;
  }
  void set_reason(std::string_view reason) { reason_.assign(reason); }
  template <std::size_t N>
  void set_reason(const FixedText<N>& reason) {
    reason_.assign(reason.view());
  }
  template <std::size_t N>
  void set_phase(std::string_view phase, const FixedText<N>& reason) {
    set_phase(phase, reason.view());
  }
  template <std::size_t M, std::size_t N>
  void set_phase(const FixedText<M>& phase, const FixedText<N>& reason) {
    set_phase(phase.view(), reason.view());
  }

 private:
  FixedText<24> name_;
  FixedText<24> phase_;
  ReasonText reason_;
  bool phase_changed_ = false;
};

/// Builds the task for one TaskConfig (navigation points through `frame`). Throws
/// std::invalid_argument on invalid engine parameters.
std::unique_ptr<Task> make_task(const config::TaskConfig& task, const config::MissionConfig& m,
                                const core::LocalFrame& frame);

/// Formats into a ReasonText without allocating (printf-style).
ReasonText reason_printf(const char* fmt, ...) __attribute__((format(printf, 1, 2)));

/// LED colour for a recognised colour (orange shows yellow, black shows nothing).
msg::LedColour led_for(msg::Colour colour);

/// Closest lidar return within +-window_deg of a body bearing; empty when none.
std::optional<double> range_near(const perception::RangeProfile& profile, double bearing_deg,
                                 double window_deg);

}  // namespace coxswain::mission::detail
