// SPDX-License-Identifier: Apache-2.0
// coxswain-sim: check, generate and draw course files; drive the simulated boat with fixed
// commands; sail the real mission core in lockstep (`run`, `batch`); run the unmodified daemon
// against the device emulators in real time (`devices`).
#include <CLI/CLI.hpp>

#include "commands.hpp"

int main(int argc, char** argv) {
  CLI::App app{"coxswain-sim: the coxswain simulator (courses, boat dynamics, scoring)"};
  app.require_subcommand(1);
  int exit_code = 0;
  coxswain::sim::app::add_course_commands(app, exit_code);
  coxswain::sim::app::add_run_commands(app, exit_code);
  coxswain::sim::app::add_devices_command(app, exit_code);
  coxswain::sim::app::add_camera_commands(app, exit_code);
  CLI11_PARSE(app, argc, argv);
  return exit_code;
}
