// SPDX-License-Identifier: Apache-2.0
#pragma once
// Command-line parsing shared by `coxswain` and `coxswain-sim`, so both answer a usage error
// the way the documentation promises: exit status 2, the problem on one line and a one-line
// hint naming the help of the (sub)command that was being parsed. CLI11's own codes (105-114)
// are not part of the documented interface. --help and --version still exit 0.
#include <CLI/CLI.hpp>

#include <iostream>
#include <optional>
#include <string>

namespace coxswain::app {

inline constexpr int kExitUsage = 2;

/// The command path of the deepest subcommand that was parsed ("coxswain replay").
inline std::string parsed_command_path(const CLI::App& app, const std::string& program) {
  std::string path = program;
  const CLI::App* at = &app;
  for (;;) {
    const auto subs = at->get_subcommands();  // the parsed ones, in order
    if (subs.empty()) break;
    at = subs.back();
    path += " " + at->get_name();
  }
  return path;
}

/// Clears the shown default of options whose default is an empty list ("[]" says nothing), in
/// `app` and every subcommand; call once every option is added.
inline void hide_empty_list_defaults(CLI::App& app) {
  for (CLI::Option* option : app.get_options([](CLI::Option*) { return true; })) {
    if (option->get_default_str() == "[]") option->default_str("");
  }
  for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) {
    hide_empty_list_defaults(*sub);
  }
}

/// Parses argv. Null when parsing succeeded (subcommand callbacks have run); otherwise the
/// exit status: 0 after --help or --version, kExitUsage after a usage error (written to `err`).
inline std::optional<int> parse_command_line(CLI::App& app, int argc, const char* const* argv,
                                             const std::string& program, std::ostream& out,
                                             std::ostream& err) {
  hide_empty_list_defaults(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e, out, err);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e, out, err);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e, out, err);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e, out, err);
    const std::string path = parsed_command_path(app, program);
    err << path << ": " << e.what() << "\n"
        << "Try '" << path << " --help' for the options.\n";
    return kExitUsage;
  }
  return std::nullopt;
}

}  // namespace coxswain::app
