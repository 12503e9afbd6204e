// SPDX-License-Identifier: Apache-2.0
#include "coxswain/replay/info.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <map>
#include <memory>
#include <optional>
#include <regex>
#include <sstream>

#include "coxswain/record/layouts.hpp"
#include "coxswain/record/mcap_reader.hpp"
#include "coxswain/record/proto_codec.hpp"
#include "coxswain/replay/replay.hpp"

namespace coxswain::replay {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::string config_hash(std::string_view text) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (const char c : text) {
    h ^= static_cast<std::uint8_t>(c);
    h *= 0x100000001b3ULL;
  }
  char buf[24];
  std::snprintf(buf, sizeof buf, "fnv1a:%016llx", static_cast<unsigned long long>(h));
  return buf;
}

std::string size_text(std::uint64_t bytes) {
  char buf[32];
  if (bytes >= (1U << 20U)) {
    std::snprintf(buf, sizeof buf, "%.1f MiB", static_cast<double>(bytes) / 1048576.0);
  } else if (bytes >= 1024U) {
    std::snprintf(buf, sizeof buf, "%.1f KiB", static_cast<double>(bytes) / 1024.0);
  } else {
    std::snprintf(buf, sizeof buf, "%llu B", static_cast<unsigned long long>(bytes));
  }
  return buf;
}

double rounded(double value, double scale) { return std::round(value * scale) / scale; }

}  // namespace

std::string format_utc(std::int64_t utc_ns) {
  const auto seconds = static_cast<std::time_t>(utc_ns / 1'000'000'000);
  std::tm tm{};
  gmtime_r(&seconds, &tm);
  char buf[32];
  (void)std::strftime(buf, sizeof buf, "%Y-%m-%d %H:%M:%S UTC", &tm);
  return buf;
}

RecordingInfo recording_info(const fs::path& mcap) {
  RecordingInfo info;
  record::McapReader reader;
  if (!reader.open(mcap)) {
    info.error = "cannot read " + mcap.string();
    return info;
  }
  info.file_bytes = reader.file_size();
  struct Counts {
    std::uint64_t messages = 0;
    std::uint64_t bytes = 0;
  };
  std::map<std::uint16_t, Counts> counts;
  std::optional<std::uint64_t> first_ns;
  std::uint64_t last_ns = 0;
  std::map<std::string, std::uint64_t> dropped_by_topic;
  // The recorder reports drops as a running total per topic; the highest total seen is the
  // count (a rate-limited run of such lines still carries the last total in its summary).
  const std::regex dropped_line(R"(recorder: dropped \d+ messages on (\S+) \(total (\d+)\))");
  std::vector<std::uint8_t> last_tick;
  const auto topic_of = [&](std::uint16_t id) -> const std::string& {
    return reader.channels().at(id).topic;
  };
  const record::McapReadReport report = reader.read([&](const record::McapMessageView& m) {
    Counts& c = counts[m.channel_id];
    ++c.messages;
    c.bytes += m.data.size();
    if (!first_ns || m.log_time_ns < *first_ns) first_ns = m.log_time_ns;
    last_ns = std::max(last_ns, m.log_time_ns);
    const std::string& topic = topic_of(m.channel_id);
    if (topic == "/tick") {
      ++info.ticks;
      last_tick.assign(m.data.begin(), m.data.end());
    } else if (topic == "/params") {
      ++info.parameter_sets;
    } else if (topic == "/log") {
      const json j = json::parse(m.data.begin(), m.data.end(), nullptr, false);
      if (!j.is_object()) return;
      const int level = j.value("level", 0);
      if (level == 3) ++info.log_warnings;
      if (level >= 4) ++info.log_errors;
      const std::string text = j.value("message", std::string());
      if (text.starts_with("mission finished")) info.finished = true;
      if (text.starts_with("mission: ")) info.last_transition = text.substr(9);
      auto begin = std::sregex_iterator(text.begin(), text.end(), dropped_line);
      for (auto it = begin; it != std::sregex_iterator(); ++it) {
        std::uint64_t& d = dropped_by_topic[(*it)[1].str()];
        d = std::max<std::uint64_t>(d, std::stoull((*it)[2].str()));
      }
    }
  });
  if (!report.header_ok) {
    info.error = "not an MCAP file: " + mcap.string();
    return info;
  }
  info.ok = true;
  info.complete = report.complete;
  info.truncated = report.truncated;
  info.crc_ok = report.chunk_crc_errors == 0 && report.error.empty() &&
                (!report.complete || (report.data_crc_ok && report.summary_crc_ok));
  info.messages = report.messages;
  info.duration_s = first_ns ? static_cast<double>(last_ns - *first_ns) * 1e-9 : 0.0;
  if (const auto it = report.metadata.find("coxswain"); it != report.metadata.end()) {
    if (const auto v = it->second.find("build_version"); v != it->second.end()) {
      info.build_version = v->second;
    }
    if (const auto v = it->second.find("utc_ns_at_start"); v != it->second.end()) {
      info.utc_start_ns = std::strtoll(v->second.c_str(), nullptr, 10);
    }
  }
  if (const auto it = report.metadata.find("config"); it != report.metadata.end()) {
    if (const auto y = it->second.find("yaml"); y != it->second.end()) {
      info.config_hash = config_hash(y->second);
      config::ConfigErrors errors;
      if (const auto config = configuration_from_yaml(y->second, errors)) {
        info.mission = config->mission.name;
      }
    }
  }
  record::Encoding encoding = record::Encoding::kProtobuf;
  if (const auto tick_id = reader.channel_id("/tick");
      !last_tick.empty() && tick_id &&
      record::encoding_of(reader.channels().at(*tick_id).message_encoding, encoding)) {
    auto tick = std::make_unique<record::TickRecordData>();  // a snapshot holds a 64 KiB scan
    if (record::decode_tick(encoding, last_tick, *tick)) info.final_state = tick->state_path;
  }
  for (const auto& [id, channel] : reader.channels()) {
    ChannelSummary s;
    s.topic = channel.topic;
    if (const auto schema = reader.schemas().find(channel.schema_id);
        schema != reader.schemas().end()) {
      s.schema = schema->second.name;
    }
    if (const auto c = counts.find(id); c != counts.end()) {
      s.messages = c->second.messages;
      s.bytes = c->second.bytes;
    }
    s.rate_hz = info.duration_s > 0.0 ? static_cast<double>(s.messages) / info.duration_s : 0.0;
    if (const auto d = dropped_by_topic.find(s.topic); d != dropped_by_topic.end()) {
      s.dropped = d->second;
    }
    info.dropped += s.dropped;
    info.channels.push_back(std::move(s));
  }
  std::sort(info.channels.begin(), info.channels.end(),
            [](const ChannelSummary& a, const ChannelSummary& b) { return a.topic < b.topic; });
  return info;
}

std::string format_info(const RecordingInfo& info) {
  std::ostringstream out;
  if (!info.ok) {
    out << info.error << "\n";
    return out.str();
  }
  char line[256];
  out << "file: " << size_text(info.file_bytes) << ", "
      << (info.complete ? "complete" : (info.truncated ? "truncated (cut short)" : "incomplete"))
      << ", " << (info.crc_ok ? "every CRC valid" : "CRC or format errors") << "\n";
  if (!info.build_version.empty() || info.utc_start_ns != 0) {
    out << "recorded by: " << (info.build_version.empty() ? "?" : info.build_version);
    if (info.utc_start_ns != 0) out << ", started " << format_utc(info.utc_start_ns);
    out << "\n";
  }
  std::snprintf(line, sizeof line, "duration: %.2f s, %llu messages, %llu ticks\n", info.duration_s,
                static_cast<unsigned long long>(info.messages),
                static_cast<unsigned long long>(info.ticks));
  out << line;
  out << "mission: " << (info.mission.empty() ? "?" : info.mission)
      << ", result: " << (info.finished ? "finished" : "not finished") << ", final state "
      << (info.final_state.empty() ? "?" : info.final_state);
  if (!info.last_transition.empty()) out << " (last transition " << info.last_transition << ")";
  out << "\n";
  out << "configuration: " << (info.config_hash.empty() ? "not recorded" : info.config_hash) << ", "
      << info.parameter_sets << " live parameter set" << (info.parameter_sets == 1 ? "" : "s")
      << "\n";
  out << "log: " << info.log_warnings << " warnings, " << info.log_errors << " errors\n";
  out << "drops: " << info.dropped << "\n";
  std::snprintf(line, sizeof line, "%-18s %9s %10s %10s %8s  %s\n", "channel", "messages", "rate",
                "size", "dropped", "schema");
  out << line;
  for (const ChannelSummary& c : info.channels) {
    char rate[32];
    std::snprintf(rate, sizeof rate, "%.1f Hz", c.rate_hz);
    std::snprintf(line, sizeof line, "%-18s %9llu %10s %10s %8llu  %s\n", c.topic.c_str(),
                  static_cast<unsigned long long>(c.messages), rate, size_text(c.bytes).c_str(),
                  static_cast<unsigned long long>(c.dropped), c.schema.c_str());
    out << line;
  }
  return out.str();
}

std::string info_json(const RecordingInfo& info) {
  json channels = json::array();
  for (const ChannelSummary& c : info.channels) {
    channels.push_back({{"topic", c.topic},
                        {"schema", c.schema},
                        {"messages", c.messages},
                        {"bytes", c.bytes},
                        {"rate_hz", rounded(c.rate_hz, 1000.0)},
                        {"dropped", c.dropped}});
  }
  json j = {{"ok", info.ok},
            {"file_bytes", info.file_bytes},
            {"complete", info.complete},
            {"truncated", info.truncated},
            {"crc_ok", info.crc_ok},
            {"build_version", info.build_version},
            {"utc_start_ns", info.utc_start_ns},
            {"duration_s", rounded(info.duration_s, 1000.0)},
            {"messages", info.messages},
            {"ticks", info.ticks},
            {"mission", info.mission},
            {"finished", info.finished},
            {"final_state", info.final_state},
            {"last_transition", info.last_transition},
            {"config_hash", info.config_hash},
            {"parameter_sets", info.parameter_sets},
            {"log_warnings", info.log_warnings},
            {"log_errors", info.log_errors},
            {"dropped", info.dropped},
            {"channels", std::move(channels)}};
  if (!info.ok) j["error"] = info.error;
  return j.dump(-1, ' ', false, json::error_handler_t::replace);
}

}  // namespace coxswain::replay
