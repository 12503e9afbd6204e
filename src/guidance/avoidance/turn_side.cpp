// SPDX-License-Identifier: Apache-2.0
#include "coxswain/guidance/turn_side.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "coxswain/core/angles.hpp"

namespace coxswain::guidance {
namespace {

constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;
constexpr double kSampleStepM = 0.1;  // along an obstacle segment
constexpr double kMaxCommandDeg = 90.0;
constexpr double kMoreRoomDeg = 30.0;  // neither way clear: the long one only with this much more

struct Point {
  double x = 0.0;
  double y = 0.0;
};

/// The starboard turn (a port turn is measured on the obstacles mirrored): the pivot runs on a
/// circle about C = (pivot, R). Bearings about C are measured as headings are (atan2(y, x), so a
/// starboard turn adds to them); the pivot starts at -90.
class StarboardSweep {
 public:
  StarboardSweep(const TurnHull& h, double clearance_m)
      : centre_{h.pivot_ahead_m, h.turn_radius_m} {
    const double stern_x = h.bow_ahead_m - h.hull_length_m;
    const std::array<Point, 4> corners{{{h.bow_ahead_m, h.half_beam_m},
                                        {h.bow_ahead_m, -h.half_beam_m},
                                        {stern_x, h.half_beam_m},
                                        {stern_x, -h.half_beam_m}}};
    double outer = 0.0;
    for (const Point& c : corners) {
      const double dx = c.x - centre_.x;
      const double dy = c.y - centre_.y;
      outer = std::max(outer, std::hypot(dx, dy));
      // How far round ahead of the pivot the hull reaches (negative when the pivot lies ahead of
      // the bow, as for a stern-driven hull).
      bow_lead_deg_ = std::max(bow_lead_deg_, core::wrap_deg(lead_deg(c)));
    }
    // The hull spans the pivot's abscissa (stern behind it, bow ahead), so its nearest point to
    // the centre is on its inner side abeam the pivot.
    inner_m_ = std::max(0.0, h.turn_radius_m - h.half_beam_m - clearance_m);
    outer_m_ = outer + clearance_m;
  }

  /// Degrees of turn before `p` is reached; kFullTurnDeg when the sweep never reaches it.
  [[nodiscard]] double room_deg(Point p) const {
    const double d = std::hypot(p.x - centre_.x, p.y - centre_.y);
    if (d < inner_m_ || d > outer_m_) return TurnRoom::kFullTurnDeg;
    const double lead = lead_deg(p);
    // Beside or behind the hull at the start: the turn moves away from it.
    if (lead > TurnRoom::kFullTurnDeg - kBehindDeg) return TurnRoom::kFullTurnDeg;
    return std::max(0.0, lead - bow_lead_deg_);
  }

  /// Nearest and farthest distance of a segment from the centre: whether it can reach the ring.
  [[nodiscard]] bool may_touch(Point a, Point b) const {
    const double far = std::max(std::hypot(a.x - centre_.x, a.y - centre_.y),
                                std::hypot(b.x - centre_.x, b.y - centre_.y));
    if (far < inner_m_) return false;
    const double ux = b.x - a.x;
    const double uy = b.y - a.y;
    const double len2 = ux * ux + uy * uy;
    double t = 0.0;
    if (len2 > 0.0) {
      t = std::clamp(((centre_.x - a.x) * ux + (centre_.y - a.y) * uy) / len2, 0.0, 1.0);
    }
    return std::hypot(a.x + t * ux - centre_.x, a.y + t * uy - centre_.y) <= outer_m_;
  }

 private:
  // Obstacles this far round behind the pivot lie beside the hull or astern at the start.
  static constexpr double kBehindDeg = 120.0;

  /// Bearing of `p` about the centre, measured from the pivot's start (-90), in [0, 360).
  [[nodiscard]] double lead_deg(Point p) const {
    const double bearing = std::atan2(p.y - centre_.y, p.x - centre_.x) * kRadToDeg;
    return core::wrap_deg_360(bearing + 90.0);
  }

  Point centre_;
  double inner_m_ = 0.0;
  double outer_m_ = 0.0;
  double bow_lead_deg_ = -180.0;
};

double segment_room_deg(const StarboardSweep& sweep, Point a, Point b, double so_far_deg) {
  if (!sweep.may_touch(a, b)) return so_far_deg;
  const double len = std::hypot(b.x - a.x, b.y - a.y);
  const auto steps = static_cast<int>(std::ceil(len / kSampleStepM));
  double room = so_far_deg;
  for (int i = 0; i <= steps; ++i) {
    const double t = steps > 0 ? static_cast<double>(i) / static_cast<double>(steps) : 0.0;
    room = std::min(room, sweep.room_deg({a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)}));
  }
  return room;
}

}  // namespace

std::optional<std::string> TurnSideParams::validate() const {
  if (!(min_turn_deg >= 0.0 && min_turn_deg <= 180.0)) return "min_turn_deg must be in [0, 180]";
  if (!(clearance_m >= 0.0 && clearance_m <= 10.0)) return "clearance_m must be in [0, 10]";
  if (!(release_deg > 0.0 && release_deg <= 90.0)) return "release_deg must be in (0, 90]";
  if (!(turn_radius_m > 0.0 && turn_radius_m <= 50.0)) return "turn_radius_m must be in (0, 50]";
  return std::nullopt;
}

TurnRoom turn_room(const perception::ObstacleList& obstacles, const TurnHull& hull,
                   double clearance_m) {
  const StarboardSweep sweep(hull, clearance_m);
  TurnRoom room;
  for (std::uint32_t i = 0; i < obstacles.count; ++i) {
    const perception::ObstacleSegment& s = obstacles.segments[i];
    const Point a{s.begin.forward_m, s.begin.starboard_m};
    const Point b{s.end.forward_m, s.end.starboard_m};
    room.starboard_deg = segment_room_deg(sweep, a, b, room.starboard_deg);
    // Port: the same sweep on the mirrored scene.
    room.port_deg = segment_room_deg(sweep, {a.x, -a.y}, {b.x, -b.y}, room.port_deg);
  }
  return room;
}

bool inside_turning_circle(core::BodyPoint target, const TurnHull& hull, double tolerance_m) {
  const double side = target.starboard_m >= 0.0 ? 1.0 : -1.0;
  const double d = std::hypot(target.forward_m - hull.pivot_ahead_m,
                              target.starboard_m - side * hull.turn_radius_m);
  return d < hull.turn_radius_m - tolerance_m;
}

double TurnSideChooser::steer(double heading_deg, double desired_deg) {
  const double err = core::angle_diff_deg(desired_deg, heading_deg);
  if (side_ != Side::kShortest) {
    const double dir = side_ == Side::kStarboard ? 1.0 : -1.0;
    const double remaining = core::wrap_deg_360(dir * err);
    if (remaining <= p_.release_deg) {
      side_ = Side::kShortest;
      return desired_deg;
    }
    return core::wrap_deg(heading_deg + dir * std::min(remaining, kMaxCommandDeg));
  }
  if (!p_.enabled || !room_ || std::abs(err) < p_.min_turn_deg) return desired_deg;
  const double need_starboard = core::wrap_deg_360(err);
  const double need_port = TurnRoom::kFullTurnDeg - need_starboard;
  const bool starboard_is_short = err >= 0.0;
  const double room_short = starboard_is_short ? room_->starboard_deg : room_->port_deg;
  const double need_short = starboard_is_short ? need_starboard : need_port;
  const double room_long = starboard_is_short ? room_->port_deg : room_->starboard_deg;
  const double need_long = starboard_is_short ? need_port : need_starboard;
  // The short way when it is clear; else the long way when that is clear, or when neither is
  // but the long way has clearly more room (a waypoint in a corner: the wall met later). The
  // side is then held to the end of the turn: near +-180 degrees the heading controller would
  // otherwise keep whichever way it was already turning.
  const bool take_long =
      room_short < need_short && (room_long >= need_long || room_long >= room_short + kMoreRoomDeg);
  side_ = starboard_is_short != take_long ? Side::kStarboard : Side::kPort;
  const double dir = side_ == Side::kStarboard ? 1.0 : -1.0;
  return core::wrap_deg(heading_deg +
                        dir * std::min(take_long ? need_long : need_short, kMaxCommandDeg));
}

}  // namespace coxswain::guidance
