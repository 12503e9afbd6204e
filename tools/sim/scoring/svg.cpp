// SPDX-License-Identifier: Apache-2.0
#include <algorithm>
#include <iomanip>
#include <sstream>

#include "sim/scoring/scorer.hpp"

namespace coxswain::sim::scoring {
namespace {

using core::NavPoint;

std::string css_colour(msg::Colour c) {
  switch (c) {
    case msg::Colour::kRed:
      return "#d62728";
    case msg::Colour::kGreen:
      return "#2ca02c";
    case msg::Colour::kBlue:
      return "#1f77b4";
    case msg::Colour::kYellow:
      return "#e6c700";
    case msg::Colour::kOrange:
      return "#ff7f0e";
    case msg::Colour::kPurple:
      return "#9467bd";
    case msg::Colour::kBlack:
      return "#000000";
    case msg::Colour::kWhite:
      return "#f0f0f0";
    case msg::Colour::kUnknown:
      break;
  }
  return "#888888";
}

// SVG x = east, y = -north, so north is up.
std::string xy(NavPoint p) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(3) << p.east_m << "," << -p.north_m;
  return s.str();
}

std::string polyline(const std::vector<NavPoint>& pts) {
  std::string out;
  for (const auto& p : pts) out += xy(p) + " ";
  return out;
}

}  // namespace

std::string trajectory_svg(const world::World& w, const config::HullConfig& hull,
                           const std::vector<core::NavPose>& path, const ScoreResult* result) {
  double n0 = w.start.position.north_m;
  double n1 = n0;
  double e0 = w.start.position.east_m;
  double e1 = e0;
  auto extend = [&](NavPoint p) {
    n0 = std::min(n0, p.north_m);
    n1 = std::max(n1, p.north_m);
    e0 = std::min(e0, p.east_m);
    e1 = std::max(e1, p.east_m);
  };
  for (const auto& wall : w.walls) std::for_each(wall.points.begin(), wall.points.end(), extend);
  for (const auto& b : w.buoys) extend(b.center);
  for (const auto& wp : w.waypoints) extend(wp.position);
  for (const auto& r : w.regions) std::for_each(r.polygon.begin(), r.polygon.end(), extend);
  for (const auto& p : path) extend(p.position);
  const double pad = 2.0;
  std::ostringstream o;
  o << std::fixed << std::setprecision(3);
  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"" << e0 - pad << " " << -(n1 + pad)
    << " " << (e1 - e0 + 2 * pad) << " " << (n1 - n0 + 2 * pad) << "\" width=\""
    << std::max(200.0, (e1 - e0 + 2 * pad) * 20.0) << "\" height=\""
    << std::max(200.0, (n1 - n0 + 2 * pad) * 20.0) << "\">\n";
  o << "<title>" << w.name << "</title>\n";
  o << "<rect x=\"" << e0 - pad << "\" y=\"" << -(n1 + pad) << "\" width=\"" << (e1 - e0 + 2 * pad)
    << "\" height=\"" << (n1 - n0 + 2 * pad) << "\" fill=\"#dbeef7\"/>\n";
  for (const auto& r : w.regions) {
    o << "<polygon class=\"region\" points=\"" << polyline(r.polygon)
      << "\" fill=\"none\" stroke=\"#7f7f7f\" stroke-width=\"0.08\" stroke-dasharray=\"0.5,0.3\"/>"
      << "\n";
  }
  for (const auto& wall : w.walls) {
    o << "<polyline class=\"wall\" points=\"" << polyline(wall.points)
      << "\" fill=\"none\" stroke=\"#333\" stroke-width=\"0.15\"/>\n";
  }
  for (const auto& d : w.docks) {
    const bool target = d.marker.colour == w.target_colour && d.marker.shape == w.target_shape;
    for (const auto& wall : d.walls) {
      o << "<polyline class=\"dock\" points=\"" << polyline(wall.points)
        << "\" fill=\"none\" stroke=\"" << (target ? "#d62728" : "#8c564b")
        << "\" stroke-width=\"0.12\"/>\n";
    }
    o << "<circle class=\"marker\" cx=\"" << d.marker.center.east_m << "\" cy=\""
      << -d.marker.center.north_m << "\" r=\"0.25\" fill=\"" << css_colour(d.marker.colour)
      << "\"><title>" << d.name << ": " << msg::colour_name(d.marker.colour) << " "
      << msg::shape_name(d.marker.shape) << "</title></circle>\n";
  }
  for (const auto& b : w.buoys) {
    o << "<circle class=\"buoy\" cx=\"" << b.center.east_m << "\" cy=\"" << -b.center.north_m
      << "\" r=\"" << b.radius_m << "\" fill=\"" << css_colour(b.colour)
      << "\" stroke=\"#000\" stroke-width=\"0.03\"/>\n";
  }
  for (const auto& g : w.gates) {
    o << "<line class=\"gate\" x1=\"" << g.left.east_m << "\" y1=\"" << -g.left.north_m
      << "\" x2=\"" << g.right.east_m << "\" y2=\"" << -g.right.north_m
      << "\" stroke=\"#2ca02c\" stroke-width=\"0.1\" stroke-dasharray=\"0.3,0.2\"/>\n";
  }
  for (const auto& wp : w.waypoints) {
    bool reached = false;
    if (result != nullptr) {
      for (const auto& p : result->waypoints) reached = reached || p.name == wp.name;
    }
    o << "<circle class=\"waypoint\" cx=\"" << wp.position.east_m << "\" cy=\""
      << -wp.position.north_m << "\" r=\"" << wp.radius_m << "\" fill=\""
      << (reached ? "#2ca02c" : "none") << "\" fill-opacity=\"0.3\" stroke=\"#2ca02c\""
      << " stroke-width=\"0.06\"><title>" << wp.name << "</title></circle>\n";
  }
  if (!path.empty()) {
    o << "<polyline class=\"path\" points=\"";
    for (const auto& p : path) o << xy(p.position) << " ";
    o << "\" fill=\"none\" stroke=\"#1f3fbf\" stroke-width=\"0.06\"/>\n";
    std::vector<NavPoint> outline;
    for (const auto& p : hull_outline(hull, path.back())) outline.push_back(p);
    o << "<polygon class=\"hull\" points=\"" << polyline(outline)
      << "\" fill=\"#1f3fbf\" fill-opacity=\"0.4\" stroke=\"#1f3fbf\" stroke-width=\"0.03\"/>\n";
  }
  {
    std::vector<NavPoint> outline;
    for (const auto& p : hull_outline(hull, w.start)) outline.push_back(p);
    o << "<polygon class=\"start\" points=\"" << polyline(outline)
      << "\" fill=\"none\" stroke=\"#555\" stroke-width=\"0.03\"/>\n";
  }
  if (result != nullptr) {
    for (const auto& c : result->contacts) {
      const double s = 0.35;
      const double x = c.at.east_m;
      const double y = -c.at.north_m;
      o << "<path class=\"collision\" d=\"M" << x - s << "," << y - s << " L" << x + s << ","
        << y + s << " M" << x - s << "," << y + s << " L" << x + s << "," << y - s
        << "\" stroke=\"#d62728\" stroke-width=\"0.12\"><title>" << c.obstacle << " at " << c.t_s
        << " s</title></path>\n";
    }
  }
  o << "</svg>\n";
  return o.str();
}

}  // namespace coxswain::sim::scoring
