// SPDX-License-Identifier: Apache-2.0
#pragma once
// The parts of `coxswain-sim batch` that do not sail: which runs a shard holds, the batch's
// summary from its JSON lines (the same numbers whether the lines came from one process or from
// merged shards), reading shard files back, and mission-parameter overrides by dotted name
// through the live-tuning layer (--set, --set-file).
#include <cstddef>
#include <cstdint>
#include <istream>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "coxswain/config/config.hpp"

namespace coxswain::sim::batch {

/// The index-th of `count` disjoint parts of a batch (index 0 .. count-1, as a Slurm array's
/// SLURM_ARRAY_TASK_ID runs with --array=0-(count-1)). Run i of the batch belongs to shard
/// i % count, so every shard holds a spread of seeds and the parts together are the batch.
struct Shard {
  int index = 0;
  int count = 1;
};

/// Parses "I/N" (0 <= I < N, 1 <= N <= 100000). Null on anything else, with the reason in `why`.
[[nodiscard]] std::optional<Shard> parse_shard(std::string_view text, std::string* why);

/// The run indices (0 .. runs-1) of `shard`, ascending.
[[nodiscard]] std::vector<int> shard_runs(int runs, const Shard& shard);

/// The contest's price of one run: its score (elapsed + penalties) when it passed, else the time
/// limit plus the penalties it collected (a failure costs at least the whole time limit).
[[nodiscard]] double contest_score_s(bool passed, double score_s, double time_limit_s,
                                     double penalty_s);

/// The time limit a run is priced at when it fails: the course regions' limits when the course
/// has them (2026), else the mission tasks' limits, else the run's hard stop. A hard stop below
/// the limit (--max-time) does not lower the price.
[[nodiscard]] double run_time_limit_s(const config::MissionConfig& mission, double region_limits_s,
                                      double max_time_s);

/// `value` rounded to `decimals` places, for JSON output: 33.019999999999996 prints as 33.02.
/// Run lines carry seconds to the millisecond, the summary its rates to four places.
[[nodiscard]] double rounded(double value, int decimals = 3);

/// `text` quoted for a POSIX shell when it needs it (a reproducing command line).
[[nodiscard]] std::string shell_quote(std::string_view text);

/// Sorts run lines by seed (lines without a seed last, in their order).
void sort_by_seed(std::vector<nlohmann::json>& lines);

/// The batch summary of these run lines (sorted by seed first, so sums and percentiles come out
/// bit for bit the same whatever order the lines arrived in).
[[nodiscard]] nlohmann::json summarize(std::vector<nlohmann::json> lines, const std::string& kind,
                                       bool baseline);

/// What a set of batch or shard files holds once read.
struct Collected {
  std::vector<nlohmann::json> runs;       // run lines, sorted by seed
  std::vector<nlohmann::json> summaries;  // the shards' own summary lines
  std::string kind;
  bool baseline = false;
};

/// Reads JSON lines (run lines and summary lines; blank lines skipped) from `in`, named `name`
/// in errors. Lines over 1 MiB, lines that are not JSON objects, and more than `max_lines` lines
/// are errors. Returns false with the reason in `why`.
bool read_lines(std::istream& in, const std::string& name, Collected& into, std::string* why,
                std::size_t max_lines = 10'000'000);

/// Checks merged shard files: no seed twice, one kind, and when the shards wrote their summary
/// lines, every shard 0..N-1 present and the run count what the batch asked for. Empty when fine,
/// else what is wrong.
[[nodiscard]] std::string check_collected(const Collected& collected);

/// Sets one named mission parameter (a live-tunable name such as "avoidance.clearance_m") in
/// `mission` through the live-tuning layer's ranges and validation. Empty when set, else why not
/// (`mission` unchanged then).
[[nodiscard]] std::string set_parameter(config::MissionConfig& mission, std::string_view key,
                                        double value);

/// Parses "KEY=VALUE" (VALUE a number, or true/false) and sets it. Empty when set, else why not.
[[nodiscard]] std::string set_parameter_assignment(config::MissionConfig& mission,
                                                   std::string_view assignment);

/// Applies an overlay file: a flat YAML map of dotted parameter name to scalar value (at most
/// 1 MiB, at most 10000 keys). Empty when every key was set, else the first problem with the
/// file's name and the key.
[[nodiscard]] std::string apply_overlay_file(config::MissionConfig& mission,
                                             const std::string& path);
/// The same for the overlay's text, named `name` in problems.
[[nodiscard]] std::string apply_overlay_text(config::MissionConfig& mission,
                                             const std::string& text, const std::string& name);

}  // namespace coxswain::sim::batch
