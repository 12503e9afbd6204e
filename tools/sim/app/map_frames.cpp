// SPDX-License-Identifier: Apache-2.0
#include "map_frames.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <string>
#include <utility>

#include "coxswain/core/angles.hpp"
#include "coxswain/guidance/nav_map.hpp"

namespace coxswain::sim::app {
namespace {

constexpr int kPixelsPerCell = 3;

}  // namespace

MapFrameWriter::MapFrameWriter(std::string dir, double period_s, const world::World& world)
    : dir_(std::move(dir)), period_s_(period_s), world_(world) {
  if (!(period_s_ > 0.0)) throw std::invalid_argument("map frames: the period must be > 0");
  std::filesystem::create_directories(dir_);
}

void MapFrameWriter::on_step(double t_s, const runner::MissionPilot& pilot,
                             const core::NavPose& truth) {
  if (t_s + 1e-9 < next_s_) return;
  const guidance::NavMap* map = pilot.core().nav_map();
  const guidance::MapPlanner* planner = pilot.core().map_planner();
  if (map == nullptr) return;
  next_s_ = t_s + period_s_;
  const auto rows = static_cast<int>(map->rows());
  const auto cols = static_cast<int>(map->cols());
  // North up, east right: row r is drawn at image row (rows - 1 - r).
  cv::Mat img(rows * kPixelsPerCell, cols * kPixelsPerCell, CV_8UC3);
  const guidance::GridView view = planner != nullptr ? planner->view() : guidance::GridView{};
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      const std::size_t k = static_cast<std::size_t>(r) * map->cols() + static_cast<std::size_t>(c);
      cv::Vec3b colour;
      if (map->known(k)) {
        colour = {90, 60, 60};
      } else if (map->occupied(k)) {
        colour = {0, 0, 0};
      } else {
        const float lo = map->log_odds(k);
        if (lo == 0.0F) {
          colour = {160, 160, 160};  // never seen
        } else if (lo < 0.0F) {
          colour = {250, 235, 215};  // seen free
        } else {
          colour = {120, 120, 200};  // some evidence, below occupied
        }
      }
      if (view.state != nullptr && view.state[k] == guidance::CellState::kInflated) {
        colour = {static_cast<unsigned char>(colour[0] * 0.6),
                  static_cast<unsigned char>(colour[1] * 0.6),
                  static_cast<unsigned char>(colour[2] * 0.9)};
      }
      cv::rectangle(img,
                    cv::Rect(c * kPixelsPerCell, (rows - 1 - r) * kPixelsPerCell, kPixelsPerCell,
                             kPixelsPerCell),
                    colour, cv::FILLED);
    }
  }
  const double res = map->params().resolution_m;
  const core::NavPoint o = map->origin();
  const auto px = [&](core::NavPoint p) {
    return cv::Point(static_cast<int>(std::lround((p.east_m - o.east_m) / res * kPixelsPerCell)),
                     static_cast<int>(std::lround(rows * kPixelsPerCell -
                                                  (p.north_m - o.north_m) / res * kPixelsPerCell)));
  };
  const int px_per_m = static_cast<int>(std::lround(kPixelsPerCell / res));
  for (const world::Wall& w : world_.walls) {
    for (std::size_t i = 1; i < w.points.size(); ++i) {
      cv::line(img, px(w.points[i - 1]), px(w.points[i]), {0, 140, 0}, 1, cv::LINE_AA);
    }
  }
  for (const world::Buoy& b : world_.buoys) {
    cv::circle(img, px(b.center), std::max(1, static_cast<int>(b.radius_m * px_per_m)), {0, 140, 0},
               1, cv::LINE_AA);
  }
  if (planner != nullptr && planner->status() == guidance::PlanStatus::kOk) {
    const auto& path = planner->path();
    for (std::size_t i = 1; i < path.size(); ++i) {
      cv::line(img, px(path[i - 1]), px(path[i]), {0, 0, 230}, 2, cv::LINE_AA);
    }
  }
  const mission::VizFrame& v = pilot.output().viz;
  if (v.has_goal) cv::drawMarker(img, px(v.goal), {200, 0, 200}, cv::MARKER_CROSS, 12, 2);
  const auto arrow = [&](const core::NavPose& p, const cv::Scalar& colour) {
    const double h = core::deg_to_rad(p.heading_deg);
    const core::NavPoint tip{p.position.north_m + std::cos(h), p.position.east_m + std::sin(h)};
    cv::circle(img, px(p.position), 4, colour, cv::FILLED, cv::LINE_AA);
    cv::line(img, px(p.position), px(tip), colour, 2, cv::LINE_AA);
  };
  if (v.pose_valid) arrow(v.pose, {230, 120, 0});
  arrow(truth, {0, 180, 0});
  char text[160];
  std::snprintf(text, sizeof text, "t %.1f s  %s  plan %s", t_s,
                std::string(pilot.status().state_path.view()).c_str(),
                planner != nullptr ? guidance::to_string(planner->status()) : "-");
  cv::putText(img, text, {4, 14}, cv::FONT_HERSHEY_SIMPLEX, 0.45, {0, 0, 0}, 1, cv::LINE_AA);
  char name[64];
  std::snprintf(name, sizeof name, "/map_%07.1f.png", t_s);
  if (!cv::imwrite(dir_ + name, img)) throw std::runtime_error("map frames: cannot write " + dir_);
  ++written_;
}

}  // namespace coxswain::sim::app
