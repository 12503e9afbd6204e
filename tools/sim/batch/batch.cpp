// SPDX-License-Identifier: Apache-2.0
#include "sim/batch/batch.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "coxswain/mission/tunable_parameters.hpp"

namespace coxswain::sim::batch {
namespace {

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const double idx = p * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(idx));
  const auto hi = static_cast<std::size_t>(std::ceil(idx));
  return v[lo] + (v[hi] - v[lo]) * (idx - static_cast<double>(lo));
}

std::optional<long long> parse_int(std::string_view s) {
  long long v = 0;
  const auto* end = s.data() + s.size();
  const auto [ptr, ec] = std::from_chars(s.data(), end, v);
  if (ec != std::errc() || ptr != end || s.empty()) return std::nullopt;
  return v;
}

std::optional<double> parse_value(std::string_view s) {
  if (s == "true") return 1.0;
  if (s == "false") return 0.0;
  double v = 0.0;
  const auto* end = s.data() + s.size();
  const auto [ptr, ec] = std::from_chars(s.data(), end, v);
  if (ec != std::errc() || ptr != end || s.empty() || !std::isfinite(v)) return std::nullopt;
  return v;
}

// The fields the summary and the merge read, when present, have the types they read them as
// (so a hand-edited or corrupt line is an error, not an exception).
std::string field_types_problem(const nlohmann::json& j) {
  const auto is = [&](const char* key, auto test) { return !j.contains(key) || test(j[key]); };
  const auto boolean = [](const nlohmann::json& v) { return v.is_boolean(); };
  const auto number = [](const nlohmann::json& v) { return v.is_number(); };
  const auto integer = [](const nlohmann::json& v) {
    return v.is_number_integer() && v.get<std::int64_t>() >= -1 &&
           v.get<std::int64_t>() <= 1'000'000'000;
  };
  for (const char* key : {"summary", "passed", "baseline", "completed"}) {
    if (!is(key, boolean)) return std::string(key) + " is not true/false";
  }
  for (const char* key : {"elapsed_s", "score_s", "contest_score_s", "time_limit_s"}) {
    if (!is(key, number)) return std::string(key) + " is not a number";
  }
  for (const char* key : {"collisions", "shard", "shards", "runs_total"}) {
    if (!is(key, integer)) return std::string(key) + " is not a whole number";
  }
  for (const char* key : {"kind", "mission_state"}) {
    if (!is(key, [](const nlohmann::json& v) { return v.is_string(); })) {
      return std::string(key) + " is not a string";
    }
  }
  return {};
}

}  // namespace

std::optional<Shard> parse_shard(std::string_view text, std::string* why) {
  const auto slash = text.find('/');
  const auto fail = [&](const char* reason) -> std::optional<Shard> {
    if (why != nullptr) *why = std::string("--shard ") + std::string(text) + ": " + reason;
    return std::nullopt;
  };
  if (slash == std::string_view::npos) return fail("expected I/N");
  const auto i = parse_int(text.substr(0, slash));
  const auto n = parse_int(text.substr(slash + 1));
  if (!i || !n) return fail("I and N must be whole numbers");
  if (*n < 1 || *n > 100000) return fail("N must be 1..100000");
  if (*i < 0 || *i >= *n) return fail("I must be 0..N-1");
  return Shard{static_cast<int>(*i), static_cast<int>(*n)};
}

std::vector<int> shard_runs(int runs, const Shard& shard) {
  std::vector<int> out;
  for (int i = shard.index; i < runs; i += shard.count) out.push_back(i);
  return out;
}

double contest_score_s(bool passed, double score_s, double time_limit_s, double penalty_s) {
  return passed ? score_s : time_limit_s + penalty_s;
}

double run_time_limit_s(const config::MissionConfig& mission, double region_limits_s,
                        double max_time_s) {
  double limit = region_limits_s;
  if (limit <= 0.0) {
    for (const auto& task : mission.tasks) limit += task.time_limit_s;
  }
  // A run cut short by a hard stop below the contest's limit fails and is still priced at the
  // contest's limit (a tuner may stop hopeless runs early without making failures cheaper).
  if (limit <= 0.0) limit = max_time_s;
  return limit;
}

void sort_by_seed(std::vector<nlohmann::json>& lines) {
  std::stable_sort(lines.begin(), lines.end(),
                   [](const nlohmann::json& a, const nlohmann::json& b) {
                     const bool ha = a.contains("seed") && a["seed"].is_number_unsigned();
                     const bool hb = b.contains("seed") && b["seed"].is_number_unsigned();
                     if (ha != hb) return ha;
                     if (!ha) return false;
                     return a["seed"].get<std::uint64_t>() < b["seed"].get<std::uint64_t>();
                   });
}

double rounded(double value, int decimals) {
  if (!std::isfinite(value)) return value;
  const double scale = std::pow(10.0, decimals);
  return std::round(value * scale) / scale;
}

std::string shell_quote(std::string_view text) {
  const bool plain = !text.empty() && text.find_first_not_of(
                                          "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                          "0123456789_-+=./:,@%") == std::string_view::npos;
  if (plain) return std::string(text);
  std::string out = "'";
  for (const char c : text) {
    if (c == '\'') {
      out += "'\\''";
    } else {
      out += c;
    }
  }
  return out + "'";
}

nlohmann::json summarize(std::vector<nlohmann::json> lines, const std::string& kind,
                         bool baseline) {
  sort_by_seed(lines);
  int passed = 0;
  int collisions = 0;
  int zero = 0;
  int false_finishes =
      0;  // the mission declared itself done; the judge saw the course not completed
  double contest_sum_s = 0.0;
  std::vector<double> times;
  std::vector<double> scores;
  std::vector<double> contest;
  for (const auto& j : lines) {
    const bool ok = j.value("passed", false);
    if (ok) ++passed;
    const int c = j.value("collisions", 0);
    collisions += c;
    if (c == 0 && !j.contains("error")) ++zero;
    if (!j.value("completed", false) && j.value("mission_state", std::string()) == "finished") {
      ++false_finishes;
    }
    if (ok) {
      times.push_back(j.value("elapsed_s", 0.0));
      scores.push_back(j.value("score_s", 0.0));
    }
    const double cs = j.value("contest_score_s", 0.0);
    contest.push_back(cs);
    contest_sum_s += cs;
  }
  const int runs = static_cast<int>(lines.size());
  const double n = std::max(1, runs);
  return {{"summary", true},
          {"kind", kind},
          {"baseline", baseline},
          {"runs", runs},
          {"success_rate", rounded(passed / n, 4)},
          {"collisions", collisions},
          {"zero_collision_runs", zero},
          {"zero_collision_rate", rounded(zero / n, 4)},
          {"false_finishes", false_finishes},
          {"time_p50_s", rounded(percentile(times, 0.5))},
          {"time_p90_s", rounded(percentile(times, 0.9))},
          {"score_p50_s", rounded(percentile(scores, 0.5))},
          {"score_p90_s", rounded(percentile(scores, 0.9))},
          {"contest_score_mean_s", rounded(contest_sum_s / n)},
          {"contest_score_p90_s", rounded(percentile(contest, 0.9))}};
}

bool read_lines(std::istream& in, const std::string& name, Collected& into, std::string* why,
                std::size_t max_lines) {
  constexpr std::size_t kMaxLine = 1U << 20U;
  std::string line;
  std::size_t number = 0;
  const auto fail = [&](const std::string& reason) {
    if (why != nullptr) *why = name + ":" + std::to_string(number) + ": " + reason;
    return false;
  };
  while (std::getline(in, line)) {
    ++number;
    if (line.size() > kMaxLine) return fail("line longer than 1 MiB");
    if (into.runs.size() + into.summaries.size() >= max_lines) return fail("too many lines");
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    nlohmann::json j = nlohmann::json::parse(line, nullptr, false);
    if (j.is_discarded() || !j.is_object()) return fail("not a JSON object");
    if (const std::string problem = field_types_problem(j); !problem.empty()) return fail(problem);
    if (j.contains("kind")) {
      const std::string kind = j["kind"].get<std::string>();
      if (into.kind.empty()) into.kind = kind;
      if (kind != into.kind) return fail("kind " + kind + " mixed with " + into.kind);
    }
    if (j.contains("baseline")) into.baseline = j["baseline"].get<bool>();
    if (j.value("summary", false)) {
      into.summaries.push_back(std::move(j));
    } else {
      if (!j.contains("seed") || !j["seed"].is_number_unsigned()) return fail("run without seed");
      into.runs.push_back(std::move(j));
    }
  }
  sort_by_seed(into.runs);
  return true;
}

std::string check_collected(const Collected& c) {
  std::set<std::uint64_t> seeds;
  for (const auto& j : c.runs) {
    const auto s = j["seed"].get<std::uint64_t>();
    if (!seeds.insert(s).second) return "seed " + std::to_string(s) + " appears twice";
  }
  int shards = 0;
  int runs_total = -1;
  std::set<int> seen;
  for (const auto& s : c.summaries) {
    if (!s.contains("shard")) continue;
    const int n = s.value("shards", 0);
    if (n < 1 || n > 100000) return "a shard summary with a shard count outside 1..100000";
    if (shards != 0 && n != shards) return "shard files of different shard counts";
    shards = n;
    runs_total = s.value("runs_total", -1);
    if (!seen.insert(s.value("shard", -1)).second) {
      return "shard " + std::to_string(s.value("shard", -1)) + " appears twice";
    }
  }
  if (shards > 0) {
    for (int i = 0; i < shards; ++i) {
      if (seen.count(i) == 0) {
        return "shard " + std::to_string(i) + " of " + std::to_string(shards) +
               " is missing (its task failed or its file was not given)";
      }
    }
    if (runs_total >= 0 && static_cast<int>(c.runs.size()) != runs_total) {
      return std::to_string(c.runs.size()) + " runs in the files, the batch had " +
             std::to_string(runs_total);
    }
  }
  return {};
}

std::string set_parameter(config::MissionConfig& mission, std::string_view key, double value) {
  const mission::TunableSpec* spec = mission::find_tunable(key);
  if (spec == nullptr) return std::string(key) + ": not a tunable mission parameter";
  if (spec->group == mission::TunableGroup::kVision) {
    return std::string(key) + ": the camera's colour boxes are not set per batch";
  }
  // The live-tuning layer works on the set the core holds; the same four engine structs live in
  // the mission configuration, so the set is taken from there and written back.
  mission::TunableParameters p;
  p.heading_pid = mission.heading_pid;
  p.clustering = mission.clustering;
  p.avoidance = mission.avoidance;
  p.speed = mission.speed;
  // set_tunable's reasons name the parameter already.
  std::string problem = mission::set_tunable(p, key, value);
  if (!problem.empty()) return problem;
  mission.heading_pid = p.heading_pid;
  mission.clustering = p.clustering;
  mission.avoidance = p.avoidance;
  mission.speed = p.speed;
  return {};
}

std::string set_parameter_assignment(config::MissionConfig& mission, std::string_view assignment) {
  const auto eq = assignment.find('=');
  if (eq == std::string_view::npos || eq == 0) {
    return "--set " + std::string(assignment) + ": expected KEY=VALUE";
  }
  const auto value = parse_value(assignment.substr(eq + 1));
  if (!value) return "--set " + std::string(assignment) + ": the value is not a number";
  return set_parameter(mission, assignment.substr(0, eq), *value);
}

std::string apply_overlay_text(config::MissionConfig& mission, const std::string& text,
                               const std::string& name) {
  if (text.size() > (1U << 20U)) return name + ": larger than 1 MiB";
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    return name + ": " + e.what();
  }
  if (root.IsNull()) return {};
  if (!root.IsMap()) return name + ": expected a flat map of parameter: value";
  if (root.size() > 10000) return name + ": more than 10000 keys";
  config::MissionConfig candidate = mission;
  for (const auto& kv : root) {
    if (!kv.first.IsScalar() || !kv.second.IsScalar()) {
      return name + ": every key and value must be a scalar (a flat map of dotted names)";
    }
    const std::string key = kv.first.Scalar();
    const auto value = parse_value(kv.second.Scalar());
    std::string problem =
        value ? set_parameter(candidate, key, *value) : key + ": the value is not a number";
    if (!problem.empty()) return std::string(name).append(": ").append(problem);
  }
  mission = candidate;
  return {};
}

std::string apply_overlay_file(config::MissionConfig& mission, const std::string& path) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) return path + ": " + ec.message();
  if (size > (1U << 20U)) return path + ": larger than 1 MiB";
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return apply_overlay_text(mission, text.str(), path);
}

}  // namespace coxswain::sim::batch
