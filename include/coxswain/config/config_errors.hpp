// SPDX-License-Identifier: Apache-2.0
#pragma once
// Problems found while loading configuration: each names the file, the line and the full key,
// and all of a pass are reported together. No file format here (the readers live in src/config).
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace coxswain::config {

struct ConfigIssue {
  std::string file;
  int line = 0;  // 1-based; 0 = whole file
  std::string key;
  std::string message;
  [[nodiscard]] std::string to_string() const;
};

/// Collected problems of one validation pass. Not thread-safe (used during start-up only).
class ConfigErrors {
 public:
  void add(ConfigIssue issue) { issues_.push_back(std::move(issue)); }
  [[nodiscard]] bool empty() const { return issues_.empty(); }
  [[nodiscard]] std::size_t size() const { return issues_.size(); }
  [[nodiscard]] const std::vector<ConfigIssue>& issues() const { return issues_; }
  /// One issue per line.
  [[nodiscard]] std::string format() const;

 private:
  std::vector<ConfigIssue> issues_;
};

}  // namespace coxswain::config
