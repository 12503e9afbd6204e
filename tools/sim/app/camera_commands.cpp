// SPDX-License-Identifier: Apache-2.0
// `coxswain-sim camera render`: labelled camera frames for `coxswain vision eval`. Each frame is
// a placard with one marker (colour x shape, 0.6 m wide, 1 m above the water, 3-10 m away: the
// sizes the docking mission sees) or none, with a wall behind it now and then and up to two
// buoys, rendered by the simulator's camera at a venue preset. Frame i of seed S is the same
// scene on every machine, so a labelled set is committed as its command line, not as images.
#include <CLI/CLI.hpp>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "commands.hpp"
#include "coxswain/core/angles.hpp"
#include "sim/rng/rng.hpp"
#include "sim/sensors/camera_sim.hpp"

namespace coxswain::sim::app {
namespace {

using msg::Colour;
using msg::Shape;
using sensors::Venue;

constexpr std::array<Colour, 7> kMarkerColours{Colour::kRed,   Colour::kOrange, Colour::kYellow,
                                               Colour::kGreen, Colour::kBlue,   Colour::kPurple,
                                               Colour::kBlack};
constexpr std::array<Shape, 4> kShapes{Shape::kTriangle, Shape::kRectangle, Shape::kCross,
                                       Shape::kCircle};
constexpr std::array<Colour, 6> kBuoyColours{Colour::kRed,    Colour::kGreen,  Colour::kYellow,
                                             Colour::kOrange, Colour::kPurple, Colour::kBlue};

struct RenderOptions {
  std::string venue = "mixed";
  int count = 100;
  std::uint64_t seed = 1;
  std::string out;
  int width_px = 640;
  int height_px = 480;
  double empty_share = 0.1;  // frames without a placard
  double noise_sigma = 3.0;
};

struct Label {
  std::string colour;
  std::string shape;
  cv::Rect2d box;
  bool partial = false;
};

core::NavPoint at(double range_m, double bearing_deg) {
  return {range_m * std::cos(core::deg_to_rad(bearing_deg)),
          range_m * std::sin(core::deg_to_rad(bearing_deg))};
}

bool inside(const cv::Rect2d& b, int width, int height) {
  constexpr double kMargin = 4.0;  // the detectors cut shapes this close to the border
  return b.x > kMargin && b.y > kMargin && b.x + b.width < width - kMargin &&
         b.y + b.height < height - kMargin;
}

int render(const RenderOptions& o) {
  const std::filesystem::path dir(o.out);
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  std::ofstream csv(dir / "labels.csv");
  if (!csv) {
    std::cerr << "cannot write " << (dir / "labels.csv").string() << "\n";
    return 1;
  }
  csv << "file,colour,shape,x_px,y_px,width_px,height_px,flags\n";
  const core::NavPose pose{};  // at the origin, heading north
  cv::Mat img;
  int markers = 0;
  int buoys = 0;
  for (int i = 0; i < o.count; ++i) {
    sim::Rng rng(sim::derive_seed(o.seed, static_cast<std::uint64_t>(i)));
    sensors::CameraSimConfig cam;
    cam.width_px = o.width_px;
    cam.height_px = o.height_px;
    cam.noise_sigma = o.noise_sigma;
    cam.blur_kernel_px = 3;
    cam.seed = rng.next_u64();
    cam.venue = o.venue == "mixed" ? static_cast<Venue>(i % 4) : *sensors::parse_venue(o.venue);
    const double half_fov_deg = 0.5 * cam.hfov_deg;

    world::World w;
    std::vector<Label> labels;
    double placard_bearing_deg = 1e9;
    double max_buoy_range_m = 20.0;  // a wall hides what is behind it
    if (!rng.chance(o.empty_share)) {
      world::Dock dock;
      world::Marker& m = dock.marker;
      m.colour = kMarkerColours[rng.next_u64() % kMarkerColours.size()];
      m.shape = kShapes[rng.next_u64() % kShapes.size()];
      m.size_m = 0.6;
      m.height_m = 1.0;
      const double range_m = rng.uniform(3.0, 10.0);
      // Mostly well inside the view; one in ten near the edge (a partial view).
      const double edge_deg = rng.chance(0.1) ? half_fov_deg : half_fov_deg - 8.0;
      placard_bearing_deg = rng.uniform(-edge_deg, edge_deg);
      m.center = at(range_m, placard_bearing_deg);
      m.facing_deg = core::wrap_deg(placard_bearing_deg + 180.0 + rng.uniform(-35.0, 35.0));
      if (rng.chance(0.5)) {  // the dock wall behind the placard
        max_buoy_range_m = range_m - 0.5;
        const double back_m = range_m + 0.3;
        const double f = core::deg_to_rad(m.facing_deg);
        const core::NavPoint c = at(back_m, placard_bearing_deg);
        const double rn = std::sin(f);
        const double re = -std::cos(f);
        w.walls.push_back({{{c.north_m - 4.0 * rn, c.east_m - 4.0 * re},
                            {c.north_m + 4.0 * rn, c.east_m + 4.0 * re}},
                           0.5});
      }
      w.docks.push_back(dock);
    }
    const int buoy_count = static_cast<int>(rng.next_u64() % 3);
    for (int k = 0; k < buoy_count; ++k) {
      world::Buoy b;
      b.colour = kBuoyColours[rng.next_u64() % kBuoyColours.size()];
      const double bearing = rng.uniform(-half_fov_deg + 5.0, half_fov_deg - 5.0);
      if (std::abs(bearing - placard_bearing_deg) < 14.0) continue;  // never in front of it
      bool clear = true;
      for (const world::Buoy& other : w.buoys) {
        const double ob = core::rad_to_deg(std::atan2(other.center.east_m, other.center.north_m));
        clear = clear && std::abs(ob - bearing) > 8.0;
      }
      if (!clear) continue;
      if (max_buoy_range_m < 4.0) continue;
      b.center = at(rng.uniform(4.0, max_buoy_range_m), bearing);
      w.buoys.push_back(b);
    }

    sensors::CameraSim sim(cam, w);
    sim.render(pose, img);
    char name[32];
    std::snprintf(name, sizeof(name), "frame_%05d.png", i);
    if (!cv::imwrite((dir / name).string(), img)) {
      std::cerr << "cannot write " << (dir / name).string() << "\n";
      return 1;
    }
    for (const world::Dock& d : w.docks) {
      if (const auto box = sim.marker_box(pose, d.marker)) {
        labels.push_back({std::string(msg::colour_name(d.marker.colour)),
                          std::string(msg::shape_name(d.marker.shape)), *box,
                          !inside(*box, o.width_px, o.height_px)});
        ++markers;
      }
    }
    for (const world::Buoy& b : w.buoys) {
      if (const auto box = sim.buoy_box(pose, b)) {
        labels.push_back({std::string(msg::colour_name(b.colour)), "buoy", *box,
                          !inside(*box, o.width_px, o.height_px)});
        ++buoys;
      }
    }
    if (labels.empty()) csv << name << ",none,none,,,,,\n";
    for (const Label& l : labels) {
      csv << name << "," << l.colour << "," << l.shape << "," << std::lround(l.box.x) << ","
          << std::lround(l.box.y) << "," << std::lround(l.box.width) << ","
          << std::lround(l.box.height) << "," << (l.partial ? "partial" : "") << "\n";
    }
  }
  std::cout << "wrote " << o.count << " frames (" << markers << " markers, " << buoys
            << " buoys) and labels.csv to " << dir.string() << "\n";
  return 0;
}

}  // namespace

void add_camera_commands(CLI::App& app, int& exit_code) {
  auto* camera = app.add_subcommand("camera", "Simulated camera frames");
  camera->require_subcommand(1);
  auto* cmd = camera->add_subcommand(
      "render", "Write labelled frames (PNG + labels.csv) for `coxswain vision eval`");
  auto o = std::make_shared<RenderOptions>();
  cmd->add_option("--venue", o->venue, "pool | harbour | overcast | low_sun | mixed (in turn)")
      ->check(CLI::IsMember({"pool", "harbour", "overcast", "low_sun", "mixed"}));
  cmd->add_option("--count", o->count, "frames")->check(CLI::Range(1, 1000000));
  cmd->add_option("--seed", o->seed, "scene seed: frame i of seed S is always the same scene");
  cmd->add_option("--out", o->out, "output folder")->required();
  cmd->add_option("--width", o->width_px, "pixels")->check(CLI::Range(64, 4096));
  cmd->add_option("--height", o->height_px, "pixels")->check(CLI::Range(64, 4096));
  cmd->add_option("--empty-share", o->empty_share, "share of frames with no placard")
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--noise", o->noise_sigma, "pixel noise, grey levels")
      ->check(CLI::Range(0.0, 50.0));
  cmd->callback([o, &exit_code] { exit_code = render(*o); });
}

}  // namespace coxswain::sim::app
