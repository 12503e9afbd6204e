// SPDX-License-Identifier: Apache-2.0
#pragma once
// Running a command line from a test and reading what it wrote: the shell, its exit status, its
// standard output (and error, through files), whole files, and gzip-compressed recordings.
#include <sys/wait.h>

#include <array>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace coxswain::test {

struct CommandResult {
  int status = -1;  // exit status, -1 when the command did not exit normally
  std::string out;
  std::string err;  // empty unless the command was run with `run_to_files`
};

/// The whole file as bytes in a string; empty when it cannot be read.
inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Runs `command` with /bin/sh; standard output is captured, standard error goes where the
/// command line sends it (append "2>&1" to capture it too).
inline CommandResult run_shell(const std::string& command) {
  CommandResult r;
  FILE* p = ::popen(command.c_str(), "r");
  if (p == nullptr) return r;
  std::array<char, 4096> buf{};
  while (std::fgets(buf.data(), static_cast<int>(buf.size()), p) != nullptr) r.out += buf.data();
  const int st = ::pclose(p);
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

/// Runs `command` with its standard output and error in files under `dir` ("out", "err"), so
/// both are kept apart and nothing is lost to a full pipe.
inline CommandResult run_to_files(const std::string& command, const std::filesystem::path& dir) {
  const std::string cmd =
      command + " > '" + (dir / "out").string() + "' 2> '" + (dir / "err").string() + "'";
  const int raw = std::system(cmd.c_str());
  return {WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, slurp(dir / "out"), slurp(dir / "err")};
}

/// The decompressed bytes of a gzip file (through gzip -dc); empty on failure.
inline std::vector<std::uint8_t> gunzip(const std::filesystem::path& p, bool* ok = nullptr) {
  std::vector<std::uint8_t> out;
  const std::string cmd = "gzip -dc '" + p.string() + "'";
  FILE* pipe = ::popen(cmd.c_str(), "r");
  if (pipe == nullptr) {
    if (ok != nullptr) *ok = false;
    return out;
  }
  std::array<std::uint8_t, 65536> buf{};
  std::size_t n = 0;
  while ((n = std::fread(buf.data(), 1, buf.size(), pipe)) > 0) {
    out.insert(out.end(), buf.begin(), buf.begin() + static_cast<std::ptrdiff_t>(n));
  }
  const int st = ::pclose(pipe);
  if (ok != nullptr) *ok = st == 0;
  return out;
}

}  // namespace coxswain::test
