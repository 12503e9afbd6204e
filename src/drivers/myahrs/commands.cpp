// SPDX-License-Identifier: Apache-2.0
#include "coxswain/drivers/myahrs/commands.hpp"

#include <charconv>
#include <cmath>

namespace coxswain::drivers::myahrs {
namespace {

bool is_name_char(char c) { return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_'; }

bool is_arg_char(char c) {
  return c >= 0x20 && c <= 0x7E && c != '$' && c != '~' && c != '@' && c != '*';
}

// Known-valid fixed requests; encode_request only fails on bad input, which these are not.
EncodedCommand must(std::optional<EncodedCommand> c) { return c.value_or(EncodedCommand{}); }

}  // namespace

std::string_view EncodedCommand::name() const {
  std::string_view t = text();
  if (t.empty()) return {};
  t.remove_prefix(1);
  const std::size_t end = t.find_first_of(",*");
  return t.substr(0, end);
}

std::optional<EncodedCommand> encode_request(std::string_view name, std::string_view args) {
  if (name.empty()) return std::nullopt;
  for (const char c : name) {
    if (!is_name_char(c)) return std::nullopt;
  }
  for (const char c : args) {
    if (!is_arg_char(c)) return std::nullopt;
  }
  const std::size_t needed = 1 + name.size() + (args.empty() ? 0 : 1 + args.size()) + 5;
  if (needed > kMaxCommandBytes) return std::nullopt;

  EncodedCommand out;
  std::size_t n = 0;
  out.bytes[n++] = '@';
  for (const char c : name) out.bytes[n++] = c;
  if (!args.empty()) {
    out.bytes[n++] = ',';
    for (const char c : args) out.bytes[n++] = c;
  }
  const std::uint8_t cs = xor_checksum(std::string_view(out.bytes.data(), n));
  constexpr std::string_view kHex = "0123456789ABCDEF";
  out.bytes[n++] = '*';
  out.bytes[n++] = kHex[cs >> 4];
  out.bytes[n++] = kHex[cs & 0x0F];
  out.bytes[n++] = '\r';
  out.bytes[n++] = '\n';
  out.size = n;
  return out;
}

std::optional<EncodedCommand> mode_command(std::string_view letters) {
  if (letters.empty() || letters.size() > 2) return std::nullopt;
  for (const char c : letters) {
    if (c != 'A' && c != 'B' && c != 'C' && c != 'T') return std::nullopt;
  }
  return encode_request("mode", letters);
}

EncodedCommand continuous_mode_command(OutputForm form) {
  return must(mode_command(form == OutputForm::kAscii ? "AC" : "BC"));
}

EncodedCommand asc_out_command(Content content) {
  return must(encode_request("asc_out", content == Content::kRpyImu ? "RPYIMU" : "QUATIMU"));
}

EncodedCommand bin_out_command(Content content) {
  return must(
      encode_request("bin_out", content == Content::kRpyImu ? "EULER, IMU" : "QUATERNION, IMU"));
}

std::optional<EncodedCommand> divider_command(int divider) {
  if (divider < 1 || divider > kMaxDivider) return std::nullopt;
  std::array<char, 16> buf{};
  const auto [ptr, ec] = std::to_chars(buf.data(), buf.data() + buf.size(), divider);
  if (ec != std::errc{}) return std::nullopt;
  return encode_request("divider",
                        std::string_view(buf.data(), static_cast<std::size_t>(ptr - buf.data())));
}

EncodedCommand version_command() { return must(encode_request("version")); }
EncodedCommand trig_command() { return must(encode_request("trig")); }

int divider_for_rate(double rate_hz) {
  if (!std::isfinite(rate_hz) || rate_hz <= 0.0) return 1;
  const double d = std::round(kMaxRateHz / rate_hz);
  if (d < 1.0) return 1;
  if (d > static_cast<double>(kMaxDivider)) return kMaxDivider;
  return static_cast<int>(d);
}

std::optional<std::string> StartupParams::validate() const {
  if (!std::isfinite(rate_hz) || rate_hz <= 0.0 || rate_hz > kMaxRateHz) {
    return std::string("rate_hz must be in (0, 100]");
  }
  if (kMaxRateHz / rate_hz > static_cast<double>(kMaxDivider)) {
    return std::string("rate_hz too low: divider would exceed 1000");
  }
  return std::nullopt;
}

StartupPlan make_startup_plan(const StartupParams& params) {
  StartupPlan plan;
  // `awaits` views string literals (static storage), so plans copy safely.
  const auto add = [&plan](EncodedCommand c, std::string_view awaits) {
    plan.steps[plan.count++] = StartupStep{c, awaits};
  };
  add(must(mode_command("T")), "mode");
  add(version_command(), "version");
  add(must(divider_command(divider_for_rate(params.rate_hz))), "divider");
  if (params.form == OutputForm::kAscii) {
    add(asc_out_command(params.content), "asc_out");
  } else {
    add(bin_out_command(params.content), "bin_out");
  }
  add(continuous_mode_command(params.form), "mode");
  return plan;
}

bool is_awaited_ok(const StartupStep& step, const CommandResponse& response) {
  return response.ok && response.command == step.awaits;
}

}  // namespace coxswain::drivers::myahrs
