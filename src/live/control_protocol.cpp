// SPDX-License-Identifier: Apache-2.0
#include "coxswain/live/control_protocol.hpp"

#include <nlohmann/json.hpp>

namespace coxswain::live {
namespace {

std::vector<std::string_view> split_words(std::string_view line) {
  std::vector<std::string_view> words;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    const std::size_t begin = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
    if (i > begin) words.push_back(line.substr(begin, i - begin));
  }
  return words;
}

template <class Enum, class NameFn>
std::optional<Enum> parse_enum(std::string_view name, int last, NameFn name_of) {
  for (int v = 1; v <= last; ++v) {
    const auto e = static_cast<Enum>(v);
    if (name_of(e) == name) return e;
  }
  return std::nullopt;
}

}  // namespace

std::optional<msg::Colour> parse_colour(std::string_view name) {
  return parse_enum<msg::Colour>(name, static_cast<int>(msg::Colour::kWhite),
                                 [](msg::Colour c) { return msg::colour_name(c); });
}

std::optional<msg::Shape> parse_shape(std::string_view name) {
  return parse_enum<msg::Shape>(name, static_cast<int>(msg::Shape::kBuoy),
                                [](msg::Shape s) { return msg::shape_name(s); });
}

std::optional<ControlCommand> parse_command(std::string_view line, std::string& error) {
  const std::vector<std::string_view> words = split_words(line);
  error.clear();
  if (words.empty()) {
    error = "empty command (start, hold, resume, target <colour> <shape>, status, params)";
    return std::nullopt;
  }
  const std::string_view verb = words[0];
  const auto single = [&](CommandKind kind) -> std::optional<ControlCommand> {
    if (words.size() != 1) {
      error = std::string(verb) + " takes no arguments";
      return std::nullopt;
    }
    return ControlCommand{kind, msg::Colour::kUnknown, msg::Shape::kUnknown};
  };
  if (verb == "start") return single(CommandKind::kStart);
  if (verb == "hold") return single(CommandKind::kHold);
  if (verb == "resume") return single(CommandKind::kResume);
  if (verb == "status") return single(CommandKind::kStatus);
  if (verb == "params") return single(CommandKind::kParams);
  if (verb == "target") {
    if (words.size() != 3) {
      error = "usage: target <colour> <shape>";
      return std::nullopt;
    }
    const auto colour = parse_colour(words[1]);
    const auto shape = parse_shape(words[2]);
    if (!colour) {
      error = "unknown colour '" + std::string(words[1]) + "'";
      return std::nullopt;
    }
    if (!shape) {
      error = "unknown shape '" + std::string(words[2]) + "'";
      return std::nullopt;
    }
    return ControlCommand{CommandKind::kTarget, *colour, *shape};
  }
  error = "unknown command '" + std::string(verb) +
          "' (start, hold, resume, target <colour> <shape>, status, params)";
  return std::nullopt;
}

const msg::OperatorInput& OperatorState::apply(const ControlCommand& command, core::TimeNs now_ns) {
  switch (command.kind) {
    case CommandKind::kStart:
      ++input_.start_count;
      break;
    case CommandKind::kHold:
      ++input_.hold_count;
      input_.hold = true;
      break;
    case CommandKind::kResume:
      ++input_.hold_count;
      input_.hold = false;
      break;
    case CommandKind::kTarget:
      input_.target_colour = command.colour;
      input_.target_shape = command.shape;
      break;
    case CommandKind::kStatus:
    case CommandKind::kParams:
      break;
  }
  input_.stamp_ns = now_ns;
  return input_;
}

std::string status_json(const core::Sample<TickSummary>& tick,
                        const msg::OperatorInput& operator_input, const core::Snapshot& devices,
                        core::TimeNs now_ns) {
  nlohmann::json j;
  const mission::MissionStatus& s = tick.value.status;
  if (tick.valid()) {
    j["state_path"] = std::string(s.state_path.view());
    j["tick"] = tick.value.tick_index;
    j["tick_age_s"] = core::ns_to_sec(now_ns - tick.stamp_ns);
  } else {
    j["state_path"] = "starting";
    j["tick"] = 0;
  }
  j["started"] = s.started;
  j["finished"] = s.finished;
  j["holding"] = s.holding;
  j["hold_reason"] = std::string(mission::hold_reason_name(s.hold_reason));
  j["waiting_for"] = std::string(s.waiting_for.view());
  j["last_transition"] = std::string(s.last_transition_reason.view());
  j["task"] = s.task_index;
  j["task_count"] = s.task_count;
  j["mission_elapsed_s"] = s.mission_elapsed_s;
  j["position_valid"] = s.position_valid;
  j["heading_valid"] = s.heading_valid;
  j["operator"] = {{"start_count", operator_input.start_count},
                   {"hold_count", operator_input.hold_count},
                   {"hold", operator_input.hold},
                   {"target_colour", std::string(msg::colour_name(operator_input.target_colour))},
                   {"target_shape", std::string(msg::shape_name(operator_input.target_shape))}};
  nlohmann::json devs = nlohmann::json::object();
  bool all_ok = true;
  for (std::size_t i = 0; i < msg::kDeviceCount; ++i) {
    const auto id = static_cast<msg::DeviceId>(i);
    const core::Sample<msg::DeviceHealth>& h = devices.health[i];
    const msg::DeviceState state = h.valid() ? h.value.state : msg::DeviceState::kDisabled;
    if (state != msg::DeviceState::kDisabled && state != msg::DeviceState::kRunning) {
      all_ok = false;
    }
    devs[std::string(msg::device_name(id))] = {
        {"state", std::string(msg::device_state_name(state))},
        {"rate_hz", h.value.rate_hz},
        {"detail", std::string(h.value.detail_text())}};
  }
  j["devices"] = std::move(devs);
  j["devices_ok"] = all_ok;
  return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

bool token_matches(std::string_view configured, std::string_view presented) {
  if (configured.empty() || configured.size() != presented.size()) return false;
  unsigned char diff = 0;
  for (std::size_t i = 0; i < configured.size(); ++i) {
    diff = static_cast<unsigned char>(diff | (static_cast<unsigned char>(configured[i]) ^
                                              static_cast<unsigned char>(presented[i])));
  }
  return diff == 0;
}

}  // namespace coxswain::live
