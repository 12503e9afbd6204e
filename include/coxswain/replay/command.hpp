// SPDX-License-Identifier: Apache-2.0
#pragma once
// The `coxswain replay` subcommand behind main.cpp's CLI: exit 0 identical, 1 different, 2 the
// recording (or its configuration) is unreadable.
#include <cstddef>
#include <filesystem>
#include <ostream>

#include "coxswain/config/config.hpp"

namespace coxswain::replay {

struct ReplayCommand {
  std::filesystem::path recording;
  /// A configuration to replay with instead of the recorded one (--config-dir/--mission/...);
  /// null = the recorded effective configuration. Then the report summarises the divergence.
  const config::Configuration* config_override = nullptr;
  std::size_t max_diffs = 20;
  bool decode = false;                 // re-run the device codecs on the raw bytes instead
  bool ignore_parameter_sets = false;  // leave out the live parameter changes (/params)
  /// Not empty: write the recorded configuration files here instead of replaying.
  std::filesystem::path dump_config_dir;
};

int run_replay_command(const ReplayCommand& command, std::ostream& out, std::ostream& err);

}  // namespace coxswain::replay
