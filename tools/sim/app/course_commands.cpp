// SPDX-License-Identifier: Apache-2.0
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "commands.hpp"
#include "sim/runner/lockstep_runner.hpp"
#include "sim/scoring/scorer.hpp"
#include "sim/world/course.hpp"
#include "sim/world/generator.hpp"

namespace coxswain::sim::app {
namespace {

bool write_text(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
  if (!out) {
    std::cerr << path << ": cannot be written\n";
    return false;
  }
  return true;
}

// Plays one fixed command for the whole run.
class FixedPilot final : public runner::Pilot {
 public:
  FixedPilot(std::uint16_t ch0, std::uint16_t ch1) : pulses_{ch0, ch1} {}
  void step(const core::Snapshot& /*snapshot*/, core::TimeNs /*now_ns*/,
            msg::ActuatorCommand& out) override {
    out.pulse_us = pulses_;
    out.active = true;
  }

 private:
  std::array<std::uint16_t, 2> pulses_;
};

}  // namespace

void add_course_commands(CLI::App& app, int& exit_code) {
  CLI::App* course = app.add_subcommand("course", "check, generate, draw and drive course files");
  course->require_subcommand(1);

  auto* check = course->add_subcommand("check", "validate course files (exit 1 on any problem)");
  static std::vector<std::string> check_files;
  check->add_option("files", check_files, "course files")->required()->check(CLI::ExistingFile);
  check->callback([&exit_code] {
    for (const auto& file : check_files) {
      config::ConfigErrors errors;
      const world::Course c = world::check_course_file(file, errors);
      if (errors.empty()) {
        std::cout << file << ": ok (" << world::course_kind_name(c.world.kind) << ", "
                  << c.world.walls.size() << " walls, " << c.world.buoys.size() << " buoys, "
                  << c.world.gates.size() << " gates, " << c.world.docks.size() << " docks, "
                  << c.world.waypoints.size() << " waypoints)\n";
      } else {
        std::cerr << errors.format();
        exit_code = 1;
      }
    }
  });

  auto* gen = course->add_subcommand("generate", "write a random, solvable course from a seed");
  static std::string kind_name = "obstacle";
  static std::uint64_t seed = 1;
  static std::string out_path;
  static bool narrow = false;
  static double beam_m = 0.8;
  gen->add_option("--kind", kind_name,
                  "hopping, obstacle, docking, kaboat2026, or the obstacle families deadend, "
                  "gapwall")
      ->check([](const std::string& name) {
        return world::find_generator_kind(name) ? std::string() : "unknown kind " + name;
      });
  gen->add_option("--seed", seed, "random seed (same seed, same course)");
  gen->add_flag("--narrow", narrow, "obstacle: the narrow preliminary field");
  gen->add_option("--beam", beam_m, "hull beam the course must leave room for (m)");
  gen->add_option("-o,--output", out_path, "course file to write")->required();
  gen->callback([&exit_code] {
    const world::GeneratorKind k = *world::find_generator_kind(kind_name);
    const world::CourseKind kind = k.kind;
    world::GeneratorParams params;
    params.family = k.family;
    params.narrow = narrow;
    params.hull_beam_m = beam_m;
    const world::Course c = world::generate_course(kind, seed, params);
    if (!write_text(out_path, world::to_course_yaml(c))) exit_code = 1;
  });

  auto* svg = course->add_subcommand("svg", "draw a course file as SVG");
  static std::string svg_in;
  static std::string svg_out;
  svg->add_option("file", svg_in, "course file")->required()->check(CLI::ExistingFile);
  svg->add_option("-o,--output", svg_out, "SVG file to write")->required();
  svg->callback([&exit_code] {
    config::ConfigErrors errors;
    const world::World w = world::load_course(svg_in, errors);
    if (!errors.empty()) {
      std::cerr << errors.format();
      exit_code = 1;
      return;
    }
    if (!write_text(svg_out, scoring::trajectory_svg(w, config::HullConfig{}, {}, nullptr))) {
      exit_code = 1;
    }
  });

  auto* drive = course->add_subcommand(
      "drive", "drive the default boat (config/boat.yaml's defaults) with one fixed command");
  static std::string drive_in;
  static std::string boat_file;
  static std::uint16_t ch0 = 1500;
  static std::uint16_t ch1 = 1725;
  static double seconds = 60.0;
  static std::uint64_t drive_seed = 1;
  static std::string json_out;
  static std::string drive_svg;
  drive->add_option("file", drive_in, "course file")->required()->check(CLI::ExistingFile);
  drive->add_option("--boat", boat_file, "boat.yaml (default: built-in defaults)");
  drive->add_option("--ch0-us", ch0, "channel 0 pulse (servo, or port thruster)");
  drive->add_option("--ch1-us", ch1, "channel 1 pulse (thruster, or starboard thruster)");
  drive->add_option("--seconds", seconds, "virtual time to run");
  drive->add_option("--seed", drive_seed, "disturbance seed");
  drive->add_option("--json", json_out, "write the score as JSON here");
  drive->add_option("--svg", drive_svg, "write the trajectory picture here");
  drive->callback([&exit_code] {
    config::ConfigErrors errors;
    const world::Course c = world::load_course_file(drive_in, errors);
    config::BoatConfig boat;
    if (!boat_file.empty()) boat = config::load_boat_config(boat_file, errors);
    if (!errors.empty()) {
      std::cerr << errors.format();
      exit_code = 1;
      return;
    }
    FixedPilot pilot(ch0, ch1);
    runner::RunnerOptions options;
    options.seed = drive_seed;
    options.max_time_s = seconds;
    runner::LockstepRunner run(c, boat, options, nullptr, &pilot);
    const runner::RunOutcome out = run.run();
    const auto t = run.truth();
    std::cout << "t " << core::ns_to_sec(out.end_ns) << " s, bow at north "
              << t.pose.position.north_m << " m east " << t.pose.position.east_m << " m heading "
              << t.pose.heading_deg << " deg, speed " << t.u_mps << " m/s, collisions "
              << out.score.collisions << ", trajectory hash " << std::hex << out.trajectory_hash
              << std::dec << "\n";
    if (!json_out.empty() && !write_text(json_out, scoring::to_json(out.score).dump(2) + "\n")) {
      exit_code = 1;
    }
    if (!drive_svg.empty() &&
        !write_text(drive_svg,
                    scoring::trajectory_svg(c.world, boat.hull, run.path(), &out.score))) {
      exit_code = 1;
    }
  });
}

}  // namespace coxswain::sim::app
