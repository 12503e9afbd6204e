// SPDX-License-Identifier: Apache-2.0
// `coxswain-sim run` (one mission in lockstep on one course), `coxswain-sim batch` (generated
// courses or one course file over seeds, on a thread pool or as one shard of many, JSON lines and a
// summary) and `coxswain-sim merge` (shards back into one batch).
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "commands.hpp"
#include "coxswain/guidance/avoidance.hpp"
#include "map_frames.hpp"
#include "sim/batch/batch.hpp"
#include "sim/runner/mission_run.hpp"
#include "sim/scoring/scorer.hpp"
#include "sim/world/course.hpp"
#include "sim/world/generator.hpp"

namespace coxswain::sim::app {
namespace {

std::optional<msg::Colour> parse_colour(const std::string& name) {
  for (int i = 0; i < 16; ++i) {
    const auto c = static_cast<msg::Colour>(i);
    if (msg::colour_name(c) == name) return c;
  }
  return std::nullopt;
}

std::optional<msg::Shape> parse_shape(const std::string& name) {
  for (int i = 0; i < 8; ++i) {
    const auto s = static_cast<msg::Shape>(i);
    if (msg::shape_name(s) == name) return s;
  }
  return std::nullopt;
}

struct Files {
  std::string boat = "config/boat.yaml";
  std::string devices = "config/devices.yaml";
  std::string sensors;  // empty: built-in sensor defaults
};

bool load_common(const Files& files, config::Configuration& config,
                 sensors::SensorConfig& sensor_config, config::ConfigErrors& errors) {
  config.boat = config::load_boat_config(files.boat, errors);
  config.devices = config::load_devices_config(files.devices, errors);
  if (!files.sensors.empty()) {
    const auto s = sensors::load_sensor_config_file(files.sensors, errors);
    if (s) sensor_config = *s;
  }
  return errors.empty();
}

/// The documents' own algorithms through mission-config overrides: the 2022 selection code
/// with its defects and waypoint hopping by pure bearing (no line following).
void apply_baseline(config::MissionConfig& m) {
  m.avoidance.strategy = guidance::Strategy::kSelectionNaive2022;
  m.waypoints.line_following = false;
  // The documents took each raw fix as the position and the start point as the antenna's place.
  m.navigation.position_gain = 1.0;
  m.navigation.start_lever_arm = false;
  m.navigation.start_drift = false;
  // Nor did they plan on a map or notice a boat that made no progress.
  m.planning.planner.enabled = false;
  m.planning.planner.stuck_s = 0.0;
  m.planning.turn_side.enabled = false;
}

void print_summary_line(const std::string& label, const runner::MissionRunResult& r) {
  const auto& s = r.outcome.score;
  std::cout << label << ": " << (r.passed ? "PASS" : "FAIL") << " " << s.course << " ("
            << scoring::rules_name(s.rules) << ") t " << s.elapsed_s << " s, score " << s.score_s
            << " s, collisions " << s.collisions << ", mission " << r.status.state_path.view()
            << ", hash " << std::hex << r.outcome.trajectory_hash << std::dec << "\n";
}

/// The batch's default disturbances, drawn per seed: a 0.2 m/s current (unless the course has
/// one), a GNSS bias of up to 5 m in any direction, the site's declination, sensor noise (the
/// sensor defaults).
void apply_default_disturbances(world::Course& course, sensors::SensorConfig& sensors,
                                std::uint64_t seed) {
  // Golden-ratio sequence: directions spread evenly over seeds, reproducibly.
  const double u = std::fmod(static_cast<double>(seed) * 0.6180339887498949, 1.0);
  const double v = std::fmod(static_cast<double>(seed) * 0.7548776662466927, 1.0);
  if (course.environment.current_speed_mps == 0.0) {
    course.environment.current_speed_mps = 0.2;
    course.environment.current_toward_deg = 360.0 * u;
  }
  sensors.gnss.bias_direction_deg = 360.0 * v;
  sensors.gnss.bias_mean_m = 2.0 + 2.0 * u;  // 2..4 m, plus the wander
  sensors.gnss.bias_max_m = 5.0;
  if (course.world.declination_deg == 0.0) course.world.declination_deg = -8.5;
}

}  // namespace

void add_run_commands(CLI::App& app, int& exit_code) {
  static Files files;
  // ---- run ----
  auto* run = app.add_subcommand("run", "sail a mission on a course in lockstep (real core)");
  static std::string course_file;
  static std::string mission_file;
  static std::uint64_t seed = 1;
  static std::string out_dir;
  static std::string target_colour;
  static std::string target_shape;
  static bool no_camera = false;
  static bool baseline = false;
  static double max_time_s = 900.0;
  static bool run_disturbances = false;
  run->add_option("--course", course_file, "course file")->required()->check(CLI::ExistingFile);
  run->add_option("--mission", mission_file, "mission file")->required()->check(CLI::ExistingFile);
  run->add_option("--seed", seed, "disturbance and sensor-noise seed");
  run->add_option("--sensors", files.sensors, "simulated sensor file (config/sim/sensors.yaml)");
  run->add_option("--boat", files.boat, "boat file");
  run->add_option("--devices", files.devices, "devices file");
  run->add_option("--out", out_dir, "write result.json and track.svg here");
  static std::vector<std::string> target_words;
  run->add_option("--target", target_words,
                  "docking target COLOUR SHAPE (e.g. --target red triangle; overrides the course), "
                  "as `coxswain run --target`")
      ->expected(2);
  // The former spellings, kept working but out of the help: one name across both programs.
  run->add_option("--target-colour", target_colour)->group("");
  run->add_option("--target-shape", target_shape)->group("");
  run->add_flag("--no-camera", no_camera, "no camera frames");
  run->add_flag("--baseline", baseline, "the documents' own algorithms (2022 naive, bearing)");
  run->add_option("--max-time", max_time_s, "hard stop, simulated seconds");
  static std::string record_file;
  run->add_option("--record", record_file,
                  "write the flight recording (MCAP, as the daemon's run.mcap) to this file");
  run->add_flag("--disturbances", run_disturbances,
                "the batch's default disturbances for this seed (reproduces a batch run)");
  static std::string map_frames_dir;
  static double map_frames_every_s = 1.0;
  run->add_option("--map-frames", map_frames_dir,
                  "draw the boat's lidar map, plan, estimate and true hull as PNG frames here");
  run->add_option("--map-every", map_frames_every_s, "simulated seconds between map frames")
      ->check(CLI::PositiveNumber);
  run->callback([&exit_code] {
    config::ConfigErrors errors;
    world::Course course = world::load_course_file(course_file, errors);
    config::Configuration config;
    runner::MissionRunOptions options;
    load_common(files, config, options.sensors, errors);
    if (run_disturbances) apply_default_disturbances(course, options.sensors, seed);
    config.mission = config::load_mission_config(mission_file, errors);
    if (!errors.empty()) {
      std::cerr << errors.format();
      exit_code = 2;
      return;
    }
    config.mission = runner::fit_mission_to_course(config.mission, course.world);
    if (baseline) apply_baseline(config.mission);
    options.seed = seed;
    options.camera = !no_camera;
    options.max_time_s = max_time_s;
    options.recording_file = record_file;
    if (target_words.size() == 2) {
      target_colour = target_words[0];
      target_shape = target_words[1];
    }
    if (!target_colour.empty()) {
      const auto c = parse_colour(target_colour);
      if (!c) {
        std::cerr << "unknown colour " << target_colour << "\n";
        exit_code = 2;
        return;
      }
      options.target_colour = *c;
    }
    if (!target_shape.empty()) {
      const auto s = parse_shape(target_shape);
      if (!s) {
        std::cerr << "unknown shape " << target_shape << "\n";
        exit_code = 2;
        return;
      }
      options.target_shape = *s;
    }
    std::optional<MapFrameWriter> frames;
    if (!map_frames_dir.empty()) {
      frames.emplace(map_frames_dir, map_frames_every_s, course.world);
      options.on_step = [&frames](double t_s, const runner::MissionPilot& pilot,
                                  const core::NavPose& truth) {
        frames->on_step(t_s, pilot, truth);
      };
    }
    runner::MissionRunResult r;
    try {
      r = runner::run_mission(course, config, options);
    } catch (const std::exception& e) {
      std::cerr << "mission rejected: " << e.what() << "\n";
      exit_code = 2;
      return;
    }
    print_summary_line("run", r);
    if (!out_dir.empty()) {
      std::filesystem::create_directories(out_dir);
      std::ofstream(out_dir + "/result.json") << runner::result_json(r, seed).dump(2) << "\n";
      std::ofstream(out_dir + "/track.svg")
          << scoring::trajectory_svg(course.world, config.boat.hull, r.path, &r.outcome.score);
    }
    exit_code = r.passed ? 0 : 1;
  });

  // ---- batch ----
  auto* batch = app.add_subcommand(
      "batch", "sail generated courses (or one course file over disturbance seeds) on all cores");
  static std::string kind_name = "obstacle";
  static int runs = 100;
  static std::uint64_t seed0 = 1;
  static unsigned jobs = 0;
  static bool batch_baseline = false;
  static bool batch_no_camera = false;
  static std::string missions_dir = "config/missions";
  static std::string strategy;
  static bool no_disturbances = false;
  static std::string batch_mission;
  static std::string batch_course;
  static std::string shard_text;
  static std::vector<std::string> set_assignments;
  static std::vector<std::string> set_files;
  static double batch_max_time_s = 900.0;
  auto* kind_option =
      batch
          ->add_option("--kind", kind_name,
                       "hopping, obstacle, docking, kaboat2026, or the obstacle families "
                       "deadend, gapwall")
          ->check(CLI::IsMember(
              {"hopping", "obstacle", "docking", "kaboat2026", "deadend", "gapwall"}));
  batch
      ->add_option("--course", batch_course,
                   "sail this course file on every run (seeds vary the disturbances and noise; "
                   "the kind is the course's type)")
      ->check(CLI::ExistingFile)
      ->excludes(kind_option);
  batch->add_option("--runs", runs, "number of runs (generated courses, or seeds on --course)");
  batch->add_option("--seed0", seed0, "seed of the first course (run i uses seed0 + i)");
  batch->add_option("--jobs", jobs, "threads (default: all cores)");
  batch->add_option("--shard", shard_text,
                    "I/N: only the I-th (0..N-1) of N disjoint parts (runs i with i % N == I); "
                    "JSON lines out, combine the parts with `coxswain-sim merge`");
  batch->add_option("--set", set_assignments,
                    "KEY=VALUE: set a mission parameter by dotted name (repeatable; after "
                    "--set-file), e.g. avoidance.clearance_m=0.4");
  batch
      ->add_option("--set-file", set_files,
                   "overlay file: a flat YAML map of dotted parameter name to value "
                   "(repeatable, applied in order)")
      ->check(CLI::ExistingFile);
  batch->add_flag("--baseline", batch_baseline, "the documents' own algorithms");
  batch->add_flag("--no-camera", batch_no_camera, "no camera frames");
  batch->add_option("--missions", missions_dir, "folder of the shipped mission files");
  batch->add_option("--mission", batch_mission, "mission file (default: the kind's shipped one)");
  batch->add_option("--strategy", strategy, "avoidance strategy override");
  batch->add_option("--max-time", batch_max_time_s, "hard stop per run, simulated seconds");
  batch->add_flag("--no-disturbances", no_disturbances,
                  "no default current, GNSS bias or declination (sensor noise stays)");
  batch->add_option("--sensors", files.sensors, "simulated sensor file");
  batch->add_option("--boat", files.boat, "boat file");
  batch->add_option("--devices", files.devices, "devices file");
  batch->callback([&exit_code, &app] {
    world::CourseKind kind = world::CourseKind::kObstacle;
    config::ConfigErrors errors;
    std::optional<world::Course> fixed_course;
    if (!batch_course.empty()) {
      fixed_course = world::load_course_file(batch_course, errors);
      if (!errors.empty()) {
        std::cerr << errors.format();
        exit_code = 2;
        return;
      }
      kind = fixed_course->world.kind;
      kind_name = std::string(world::course_kind_name(kind));
    } else if (kind_name == "hopping") {
      kind = world::CourseKind::kHopping;
    } else if (kind_name == "docking") {
      kind = world::CourseKind::kDocking;
    } else if (kind_name == "kaboat2026") {
      kind = world::CourseKind::kKaboat2026;
    }
    std::string mission_name = "obstacle_course.yaml";
    if (kind == world::CourseKind::kHopping) {
      mission_name = "hopping.yaml";
    } else if (kind == world::CourseKind::kDocking) {
      mission_name = "docking.yaml";
    } else if (kind == world::CourseKind::kKaboat2026) {
      mission_name = "kaboat2026.yaml";
    }
    std::optional<batch::Shard> shard;
    if (!shard_text.empty()) {
      std::string why;
      shard = batch::parse_shard(shard_text, &why);
      if (!shard) {
        std::cerr << why << "\n";
        exit_code = 2;
        return;
      }
    }
    world::GeneratorParams generator;
    if (const auto found = world::find_generator_kind(kind_name)) generator.family = found->family;
    config::Configuration base;
    sensors::SensorConfig sensor_config;
    load_common(files, base, sensor_config, errors);
    base.mission = config::load_mission_config(
        batch_mission.empty() ? missions_dir + "/" + mission_name : batch_mission, errors);
    if (!errors.empty()) {
      std::cerr << errors.format();
      exit_code = 2;
      return;
    }
    if (batch_baseline) apply_baseline(base.mission);
    if (!strategy.empty()) {
      const auto s = guidance::parse_strategy(strategy);
      if (!s) {
        std::cerr << "unknown strategy " << strategy << "\n";
        exit_code = 2;
        return;
      }
      base.mission.avoidance.strategy = *s;
    }
    for (const auto& file : set_files) {
      const std::string problem = batch::apply_overlay_file(base.mission, file);
      if (!problem.empty()) {
        std::cerr << problem << "\n";
        exit_code = 2;
        return;
      }
    }
    for (const auto& assignment : set_assignments) {
      const std::string problem = batch::set_parameter_assignment(base.mission, assignment);
      if (!problem.empty()) {
        std::cerr << problem << "\n";
        exit_code = 2;
        return;
      }
    }
    const std::vector<int> indices =
        batch::shard_runs(std::max(runs, 0), shard.value_or(batch::Shard{}));
    const int count = static_cast<int>(indices.size());
    const unsigned n_jobs = jobs > 0 ? jobs : std::max(1U, std::thread::hardware_concurrency());
    const bool tty = isatty(STDERR_FILENO) != 0;
    std::vector<nlohmann::json> results(indices.size());
    std::atomic<int> next{0};
    std::atomic<int> done{0};
    std::mutex out_mutex;
    auto worker = [&] {
      for (;;) {
        const int k = next.fetch_add(1);
        if (k >= count) return;
        const std::uint64_t s =
            seed0 + static_cast<std::uint64_t>(indices[static_cast<std::size_t>(k)]);
        nlohmann::json j;
        try {
          world::Course course =
              fixed_course ? *fixed_course : world::generate_course(kind, s, generator);
          runner::MissionRunOptions options;
          options.sensors = sensor_config;
          if (!no_disturbances) apply_default_disturbances(course, options.sensors, s);
          config::Configuration config = base;
          config.mission = runner::fit_mission_to_course(base.mission, course.world);
          options.seed = s;
          options.camera = !batch_no_camera;
          options.record_path = false;
          options.max_time_s = batch_max_time_s;
          const runner::MissionRunResult r = runner::run_mission(course, config, options);
          const auto& sc = r.outcome.score;
          double region_limits_s = 0.0;
          for (const auto& region : course.world.regions) region_limits_s += region.time_limit_s;
          const double limit_s =
              batch::run_time_limit_s(config.mission, region_limits_s, batch_max_time_s);
          j = {{"seed", s},
               {"kind", kind_name},
               {"baseline", batch_baseline},
               {"passed", r.passed},
               {"failure", r.failure},
               {"completed", sc.completed},
               {"collisions", sc.collisions},
               {"elapsed_s", batch::rounded(sc.elapsed_s)},
               {"score_s", batch::rounded(sc.score_s)},
               {"penalty_s", batch::rounded(sc.penalty_s)},
               {"time_limit_s", batch::rounded(limit_s)},
               {"contest_score_s", batch::rounded(batch::contest_score_s(r.passed, sc.score_s,
                                                                         limit_s, sc.penalty_s))},
               {"mission_state", std::string(r.status.state_path.view())}};
        } catch (const std::exception& e) {
          j = {{"seed", s},
               {"kind", kind_name},
               {"baseline", batch_baseline},
               {"passed", false},
               {"time_limit_s", batch_max_time_s},
               {"contest_score_s", batch_max_time_s},
               {"error", e.what()}};
        }
        const std::lock_guard<std::mutex> lock(out_mutex);
        // The bar is drawn on stderr only when that is a terminal, and taken off the line
        // before each JSON line so the two never share a line when both go to the terminal.
        if (tty) std::cerr << "\r\033[K" << std::flush;
        std::cout << j.dump() << "\n" << std::flush;
        results[static_cast<std::size_t>(k)] = j;
        const int d = ++done;
        if (tty && d < count) {
          const int width = 40;
          const int filled = count > 0 ? d * width / count : width;
          std::cerr << "[" << std::string(static_cast<std::size_t>(filled), '#')
                    << std::string(static_cast<std::size_t>(width - filled), ' ') << "] " << d
                    << "/" << count << std::flush;
        }
      }
    };
    std::vector<std::thread> pool;
    for (unsigned t = 0; t < n_jobs; ++t) pool.emplace_back(worker);
    for (auto& t : pool) t.join();
    nlohmann::json summary = batch::summarize(results, kind_name, batch_baseline);
    if (shard) {
      // A shard's own summary: merge skips it for the numbers and uses it to check that every
      // shard of the batch is there.
      summary["shard"] = shard->index;
      summary["shards"] = shard->count;
      summary["runs_total"] = std::max(runs, 0);
      summary["seed0"] = seed0;
    }
    std::cout << summary.dump() << "\n" << std::flush;
    // Each failed run, with the command that sails it again alone (same options, one seed).
    std::string common = app.get_name().empty() ? "coxswain-sim" : app.get_name();
    common += " batch";
    common += batch_course.empty() ? " --kind " + batch::shell_quote(kind_name)
                                   : " --course " + batch::shell_quote(batch_course);
    if (!batch_mission.empty()) common += " --mission " + batch::shell_quote(batch_mission);
    if (missions_dir != "config/missions") {
      common += " --missions " + batch::shell_quote(missions_dir);
    }
    if (batch_baseline) common += " --baseline";
    if (batch_no_camera) common += " --no-camera";
    if (no_disturbances) common += " --no-disturbances";
    if (!strategy.empty()) common += " --strategy " + batch::shell_quote(strategy);
    if (batch_max_time_s != 900.0) {
      common += " --max-time " + nlohmann::json(batch_max_time_s).dump();  // shortest exact form
    }
    if (!files.sensors.empty()) common += " --sensors " + batch::shell_quote(files.sensors);
    if (files.boat != Files{}.boat) common += " --boat " + batch::shell_quote(files.boat);
    if (files.devices != Files{}.devices) {
      common += " --devices " + batch::shell_quote(files.devices);
    }
    for (const auto& f : set_files) common += " --set-file " + batch::shell_quote(f);
    for (const auto& a : set_assignments) common += " --set " + batch::shell_quote(a);
    int failed = 0;
    for (const auto& j : results) failed += j.value("passed", false) ? 0 : 1;
    if (failed > 0) {
      std::cerr << "failed: " << failed << " of " << count << " runs; each one again:\n";
      for (const auto& j : results) {
        if (j.value("passed", false)) continue;
        const std::string why = j.contains("error")     ? j.value("error", std::string())
                                : j.contains("failure") ? j.value("failure", std::string())
                                                        : std::string();
        std::cerr << "  seed " << j.value("seed", std::uint64_t{0}) << (why.empty() ? "" : ": ")
                  << why << "\n    " << common << " --seed0 " << j.value("seed", std::uint64_t{0})
                  << " --runs 1 --jobs 1\n";
      }
    }
  });

  // ---- merge ----
  auto* merge = app.add_subcommand(
      "merge",
      "combine the JSON lines of batch shards: their runs sorted by seed, then the "
      "summary one unsharded batch prints");
  static std::vector<std::string> merge_files;
  static bool summary_only = false;
  merge->add_option("files", merge_files, "shard files (JSON lines of `batch --shard`)")
      ->required()
      ->check(CLI::ExistingFile);
  merge->add_flag("--summary-only", summary_only, "print the summary line only");
  merge->callback([&exit_code] {
    batch::Collected collected;
    for (const auto& file : merge_files) {
      std::ifstream in(file);
      std::string why;
      if (!in || !batch::read_lines(in, file, collected, &why)) {
        std::cerr << (why.empty() ? file + ": cannot read" : why) << "\n";
        exit_code = 2;
        return;
      }
    }
    const std::string problem = batch::check_collected(collected);
    if (!problem.empty()) {
      std::cerr << "merge: " << problem << "\n";
      exit_code = 1;
      return;
    }
    if (!summary_only) {
      for (const auto& j : collected.runs) std::cout << j.dump() << "\n";
    }
    std::cout << batch::summarize(collected.runs, collected.kind, collected.baseline).dump()
              << "\n";
  });
}

}  // namespace coxswain::sim::app
