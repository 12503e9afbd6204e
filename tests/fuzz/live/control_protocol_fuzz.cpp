// SPDX-License-Identifier: Apache-2.0
// libFuzzer target for the control socket's line protocol: every line of the input is parsed as
// a command and applied to an OperatorState. Contract: a refused line says why, an accepted one
// is one of the five commands, and counters only ever grow.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

#include "coxswain/live/control_protocol.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace coxswain::live;
  std::string_view rest(reinterpret_cast<const char*>(data), size);
  OperatorState state;
  std::int64_t now_ns = 0;
  while (!rest.empty()) {
    const std::size_t nl = rest.find('\n');
    const std::string_view line = rest.substr(0, nl);
    rest = nl == std::string_view::npos ? std::string_view() : rest.substr(nl + 1);
    std::string error;
    const auto cmd = parse_command(line, error);
    if (!cmd) {
      if (error.empty()) std::abort();
      continue;
    }
    if (cmd->kind == CommandKind::kStatus) continue;
    const auto before = state.current();
    const auto& after = state.apply(*cmd, ++now_ns);
    if (after.start_count < before.start_count || after.hold_count < before.hold_count) {
      std::abort();
    }
  }
  (void)token_matches(
      std::string_view(reinterpret_cast<const char*>(data), size / 2),
      std::string_view(reinterpret_cast<const char*>(data) + size / 2, size - size / 2));
  return 0;
}
