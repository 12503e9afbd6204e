// SPDX-License-Identifier: Apache-2.0
#pragma once
// `coxswain info RUN.mcap`: what a flight recording holds, without replaying it: the file's
// soundness, who wrote it and when, the duration, each channel's message count, rate and drops,
// the mission's result and a hash of the recorded configuration (equal hashes: the same
// configuration, so two runs can be compared).
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace coxswain::replay {

struct ChannelSummary {
  std::string topic;
  std::string schema;
  std::uint64_t messages = 0;
  std::uint64_t bytes = 0;
  double rate_hz = 0.0;       // messages over the recording's duration
  std::uint64_t dropped = 0;  // counted by the recorder (its "recorder: dropped" lines on /log)
};

struct RecordingInfo {
  bool ok = false;  // the file was read as MCAP
  std::string error;
  std::uint64_t file_bytes = 0;
  bool complete = false;          // summary and footer present (a clean close)
  bool truncated = false;         // cut short (a crash or a kill): what came before was read
  bool crc_ok = false;            // no chunk failed its CRC, and the data and summary CRCs matched
  std::string build_version;      // metadata coxswain/build_version
  std::int64_t utc_start_ns = 0;  // metadata coxswain/utc_ns_at_start (0 when absent)
  double duration_s = 0.0;        // first to last message
  std::uint64_t messages = 0;
  std::vector<ChannelSummary> channels;  // by topic
  std::uint64_t dropped = 0;
  std::string mission;      // the recorded configuration's mission name
  std::string config_hash;  // "fnv1a:<16 hex>" of the recorded configuration's text
  std::uint64_t ticks = 0;
  std::string final_state;      // the last tick's state path
  bool finished = false;        // the daemon logged "mission finished"
  std::string last_transition;  // the last "mission: A -> B: reason" line
  std::uint64_t parameter_sets = 0;
  std::uint64_t log_warnings = 0;  // /log lines at warning level
  std::uint64_t log_errors = 0;    // ... at error or fatal
};

/// "2026-11-26 09:30:00 UTC" for nanoseconds since the Unix epoch.
[[nodiscard]] std::string format_utc(std::int64_t utc_ns);

/// Reads `mcap` once, front to back.
[[nodiscard]] RecordingInfo recording_info(const std::filesystem::path& mcap);
/// Human-readable, a few lines and one per channel.
[[nodiscard]] std::string format_info(const RecordingInfo& info);
/// The same as one JSON object.
[[nodiscard]] std::string info_json(const RecordingInfo& info);

}  // namespace coxswain::replay
