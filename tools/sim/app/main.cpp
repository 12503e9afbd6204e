// SPDX-License-Identifier: Apache-2.0
// coxswain-sim: check, generate and draw course files; drive the simulated boat with fixed
// commands; sail the real mission core in lockstep (`run`, `batch`); run the unmodified daemon
// against the device emulators in real time (`devices`).
#include <CLI/CLI.hpp>

#include <exception>
#include <iostream>
#include <opencv2/core/utility.hpp>
#include <string>

#include "commands.hpp"
#include "coxswain/app/cli.hpp"
#include "coxswain/version.hpp"

namespace {

int run_main(int argc, char** argv) {
  // Each lockstep world runs on one thread (a batch runs one per job); an OpenCV worker pool
  // beside them only competes for the same cores (about 5 % of a camera run's time).
  cv::setNumThreads(1);
  CLI::App app{"coxswain-sim: the coxswain simulator (courses, boat dynamics, scoring)"};
  app.set_version_flag("--version", std::string("coxswain-sim ") + coxswain::kVersion + " (git " +
                                        coxswain::kGitHash + ")");
  app.option_defaults()->always_capture_default();  // defaults shown in every --help
  app.require_subcommand(1);
  int exit_code = 0;
  coxswain::sim::app::add_course_commands(app, exit_code);
  coxswain::sim::app::add_run_commands(app, exit_code);
  coxswain::sim::app::add_devices_command(app, exit_code);
  coxswain::sim::app::add_camera_commands(app, exit_code);
  if (const auto status = coxswain::app::parse_command_line(app, argc, argv, "coxswain-sim",
                                                            std::cout, std::cerr)) {
    return *status;
  }
  return exit_code;
}

}  // namespace

int main(int argc, char** argv) {
  // Whatever escapes (a failed allocation, a library error): said in one line, never an abort.
  try {
    return run_main(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "coxswain-sim: fatal: " << e.what() << "\n";
  } catch (...) {
    std::cerr << "coxswain-sim: fatal: unknown exception\n";
  }
  return 1;
}
