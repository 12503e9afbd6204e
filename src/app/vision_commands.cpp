// SPDX-License-Identifier: Apache-2.0
#include "vision_commands.hpp"

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>

#include "coxswain/app/vision_eval.hpp"
#include "coxswain/config/vision_config.hpp"
#include "coxswain/drivers/camera/image_io.hpp"
#include "coxswain/perception/camera_pipeline.hpp"

namespace coxswain::app {
namespace {

namespace fs = std::filesystem;

struct VisionOptions {
  std::string dir;
  std::string labels;  // default DIR/labels.csv
  std::string vision;  // kind: vision file; default the built-in model
  double hfov_deg = 80.0;
  double min_recall = -1.0;
  double max_false_rate = -1.0;
  std::string out;
};

std::optional<std::vector<LabelledFrame>> load_labels(const VisionOptions& o) {
  const fs::path path = o.labels.empty() ? fs::path(o.dir) / "labels.csv" : fs::path(o.labels);
  std::ifstream in(path);
  if (!in) {
    std::cerr << "vision: cannot read " << path.string() << "\n";
    return std::nullopt;
  }
  std::string error;
  auto frames = read_labels(in, error);
  if (!frames) std::cerr << "vision: " << path.string() << ": " << error << "\n";
  return frames;
}

std::optional<perception::VisionParams> load_params(const VisionOptions& o) {
  perception::VisionParams p = perception::VisionParams::defaults();
  if (!o.vision.empty()) {
    config::ConfigErrors errors;
    const auto loaded = config::load_vision_file(o.vision, errors);
    if (!loaded) {
      std::cerr << errors.format();
      return std::nullopt;
    }
    p = *loaded;
  }
  p.hfov_deg = o.hfov_deg;
  if (const auto e = p.validate()) {
    std::cerr << "vision: " << *e << "\n";
    return std::nullopt;
  }
  return p;
}

/// Runs the pipeline over every labelled frame. nullopt when an image cannot be read.
std::optional<EvalTally> evaluate(const std::vector<LabelledFrame>& frames,
                                  const perception::VisionParams& params, const fs::path& dir) {
  perception::CameraPipeline pipeline(params);
  msg::CameraDetections out;
  EvalTally tally;
  core::TimeNs stamp_ns = 0;
  for (const LabelledFrame& f : frames) {
    std::string why;
    const cv::Mat img = drivers::camera::read_image((dir / f.file).string(), &why);
    if (img.empty()) {
      std::cerr << "vision: cannot read image " << (dir / f.file).string()
                << (why.empty() ? "" : ": " + why) << "\n";
      return std::nullopt;
    }
    const auto t0 = std::chrono::steady_clock::now();
    (void)pipeline.process(img, stamp_ns += 100'000'000, out);
    const auto t1 = std::chrono::steady_clock::now();
    tally.frame_ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    tally.add(f, out);
  }
  return tally;
}

int run_eval(const VisionOptions& o) {
  const auto frames = load_labels(o);
  const auto params = load_params(o);
  if (!frames || !params) return 2;
  const auto tally = evaluate(*frames, *params, o.dir);
  if (!tally) return 2;
  std::cout << tally->report();
  int rc = 0;
  if (o.min_recall >= 0.0 && tally->min_recall() < o.min_recall) {
    std::cout << "GATE: the lowest recall by colour or shape is " << 100.0 * tally->min_recall()
              << " %, under " << 100.0 * o.min_recall << " %\n";
    rc = 1;
  }
  if (o.max_false_rate >= 0.0 && tally->false_report_rate() > o.max_false_rate) {
    std::cout << "GATE: false reports in " << 100.0 * tally->false_report_rate()
              << " % of frames, over " << 100.0 * o.max_false_rate << " %\n";
    rc = 1;
  }
  return rc;
}

int run_calibrate(const VisionOptions& o) {
  const auto frames = load_labels(o);
  const auto base = load_params(o);
  if (!frames || !base) return 2;
  CalibrationSamples samples;
  for (const LabelledFrame& f : *frames) {
    std::string why;
    const cv::Mat img = drivers::camera::read_image((fs::path(o.dir) / f.file).string(), &why);
    if (img.empty()) {
      std::cerr << "vision: cannot read image " << (fs::path(o.dir) / f.file).string()
                << (why.empty() ? "" : ": " + why) << "\n";
      return 2;
    }
    add_calibration_samples(img, f, samples);
  }
  perception::VisionParams fitted = fit_colour_boxes(samples, *base);
  if (const auto e = fitted.validate()) {
    std::cerr << "vision: the fitted model is invalid: " << *e << "\n";
    return 2;
  }
  for (const auto& [colour, px] : samples.hsv) {
    std::cout << msg::colour_name(colour) << ": " << px.size() << " pixels\n";
  }
  if (o.out.empty()) {
    config::write_vision(fitted, std::cout);
  } else {
    std::ofstream file(o.out);
    config::write_vision(fitted, file);
    if (!file) {
      std::cerr << "vision: cannot write " << o.out << "\n";
      return 2;
    }
    std::cout << "wrote " << o.out << "\n";
  }
  // The fitted model on the same frames: a check that it took, not a measure of how it will do
  // on frames it was not fitted on (evaluate those with `vision eval --vision`).
  if (const auto tally = evaluate(*frames, fitted, o.dir)) {
    std::cout << "on the calibration frames: lowest recall " << 100.0 * tally->min_recall()
              << " %, frames with a false report " << 100.0 * tally->false_report_rate() << " %\n";
  }
  return 0;
}

void common_options(CLI::App* cmd, VisionOptions& o) {
  cmd->add_option("dir", o.dir, "Folder of images and labels.csv")->required();
  cmd->add_option("--labels", o.labels, "Labels CSV (default: DIR/labels.csv)");
  cmd->add_option("--vision", o.vision, "Colour model file (kind: vision; default: built in)");
  cmd->add_option("--hfov", o.hfov_deg, "Camera horizontal field of view, degrees")
      ->check(CLI::Range(1.0, 179.0));
}

}  // namespace

CLI::App* add_vision_commands(CLI::App& app, int& exit_code) {
  auto* vision = app.add_subcommand("vision", "Check and tune the camera detectors");
  vision->require_subcommand(1);
  auto o = std::make_shared<VisionOptions>();
  auto* eval = vision->add_subcommand(
      "eval", "Recall, precision, false reports, confusions and time per frame on labelled images");
  common_options(eval, *o);
  eval->add_option("--min-recall", o->min_recall,
                   "Gate: exit 1 when any colour's or shape's recall is below this (0..1)")
      ->check(CLI::Range(0.0, 1.0));
  eval->add_option("--max-false-rate", o->max_false_rate,
                   "Gate: exit 1 when more than this share of frames has a false report (0..1)")
      ->check(CLI::Range(0.0, 1.0));
  eval->callback([o, &exit_code] { exit_code = run_eval(*o); });
  auto* calibrate = vision->add_subcommand(
      "calibrate", "Fit the colour boxes from labelled images of the venue; write a vision file");
  common_options(calibrate, *o);
  calibrate->add_option("-o,--output", o->out, "The vision file to write (default: stdout)");
  calibrate->callback([o, &exit_code] { exit_code = run_calibrate(*o); });
  return vision;
}

}  // namespace coxswain::app
