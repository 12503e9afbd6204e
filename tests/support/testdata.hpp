// SPDX-License-Identifier: Apache-2.0
#pragma once
// Locating real recordings (the shared test data folder) and the project's own files from tests.
#include <gtest/gtest.h>

#include <filesystem>
#include <optional>
#include <string>

namespace coxswain::testing {

/// The shared test-data folder, or nullopt when this clone has none (a user's fresh clone).
inline std::optional<std::filesystem::path> shared_testdata_dir() {
  const char* env = std::getenv("COXSWAIN_SHARED_TESTDATA");
  std::filesystem::path dir = env != nullptr ? env : COXSWAIN_SHARED_TESTDATA;
  if (std::filesystem::is_directory(dir)) return dir;
  return std::nullopt;
}

inline std::filesystem::path source_dir() { return COXSWAIN_SOURCE_DIR; }

}  // namespace coxswain::testing

/// Skips the current test, naming the missing file, when the shared recordings are absent.
/// Sets `var` to the full path of `relative` inside the shared test data folder otherwise.
#define COXSWAIN_REQUIRE_TESTDATA(var, relative)                                              \
  std::filesystem::path var;                                                                  \
  do {                                                                                        \
    const auto coxswain_dir_ = ::coxswain::testing::shared_testdata_dir();                    \
    if (!coxswain_dir_) {                                                                     \
      GTEST_SKIP() << "shared test data folder (" COXSWAIN_SHARED_TESTDATA                    \
                   << ") is absent: this test needs the real recording " << (relative);       \
    }                                                                                         \
    var = *coxswain_dir_ / (relative);                                                        \
    if (!std::filesystem::exists(var)) {                                                      \
      GTEST_SKIP() << "recording " << var.string() << " is absent from the shared test data"; \
    }                                                                                         \
  } while (false)
