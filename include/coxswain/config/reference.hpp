// SPDX-License-Identifier: Apache-2.0
#pragma once
// What the parameter tables say, printed for people and tools: the reference page
// (`coxswain config doc`), the JSON Schema of each config kind (`coxswain config schema KIND`,
// shipped in schemas/ for editors) and the flat parameter list a tuner reads
// (`coxswain config params --json`).
#include <optional>
#include <string>
#include <string_view>

namespace coxswain::config {

/// Markdown: every key of every config kind with its type, unit, bounds, default, whether it
/// is live-tunable and what it does.
[[nodiscard]] std::string parameter_reference_markdown();

/// A JSON array, one object per parameter: {"key": "mission:avoidance.clearance_m", ...} with
/// type, unit, min, max, default, live, doc and, for enumerations, values.
[[nodiscard]] std::string parameters_json();

/// The JSON Schema (draft 2020-12) of a config kind: "boat", "devices" or "mission"; nullopt for
/// another name.
[[nodiscard]] std::optional<std::string> json_schema(std::string_view kind);

}  // namespace coxswain::config
