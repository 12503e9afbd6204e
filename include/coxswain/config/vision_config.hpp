// SPDX-License-Identifier: Apache-2.0
#pragma once
// The camera detectors' colour model and thresholds (perception::VisionParams) as a YAML file of
// kind `vision` (config/vision.yaml): read with validation (file, line and key in every error;
// unknown keys are errors) and written back, so a venue's tuning (`coxswain vision calibrate`,
// live changes) survives a restart. Not thread-safe; start-up and tools only.
#include <optional>
#include <ostream>
#include <string>

#include "coxswain/config/yaml_reader.hpp"
#include "coxswain/perception/vision_params.hpp"

namespace coxswain::config {

/// Reads the keys of a `vision` map over `base` (keys left out keep base's values). A `colours`
/// list, when present, replaces base's colours entirely.
[[nodiscard]] perception::VisionParams read_vision(MapReader& reader,
                                                   const perception::VisionParams& base);

/// Loads a file whose top level is `kind: vision` plus the keys read_vision takes. nullopt (with
/// `errors` filled) on any problem, including VisionParams::validate().
[[nodiscard]] std::optional<perception::VisionParams> load_vision_file(
    const std::string& path, ConfigErrors& errors,
    const perception::VisionParams& base = perception::VisionParams::defaults());

/// Writes `p` as a commented `kind: vision` file that load_vision_file reads back unchanged.
void write_vision(const perception::VisionParams& p, std::ostream& out);

}  // namespace coxswain::config
