// SPDX-License-Identifier: Apache-2.0
#include "coxswain/config/yaml_reader.hpp"

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/parser.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>

namespace coxswain::config {

std::string ConfigIssue::to_string() const {
  std::string out = file;
  if (line > 0) out += ":" + std::to_string(line);
  out += ": ";
  if (!key.empty()) out += "key '" + key + "' ";
  out += message;
  return out;
}

std::string ConfigErrors::format() const {
  std::string out;
  for (const auto& issue : issues_) out += issue.to_string() + "\n";
  return out;
}

MapReader::MapReader(const YAML::Node& node, std::string file, std::string path,
                     ConfigErrors& errors)
    : node_(node), file_(std::move(file)), path_(std::move(path)), errors_(&errors) {
  if (!node_.IsMap()) {
    // An empty document or an empty nested map is read as null: treat it as an empty map.
    if (node_.IsNull() || !node_.IsDefined()) {
      node_ = YAML::Node(YAML::NodeType::Map);
    } else {
      error("", "must be a map of key: value pairs");
      valid_ = false;
    }
  }
}

bool MapReader::has(std::string_view key) const {
  if (!valid_) return false;
  for (const auto& kv : node_) {
    if (kv.first.IsScalar() && kv.first.Scalar() == key) return true;
  }
  return false;
}

std::optional<YAML::Node> MapReader::find(std::string_view key) {
  seen_.emplace(key);
  if (!valid_) return std::nullopt;
  for (const auto& kv : node_) {
    if (kv.first.IsScalar() && kv.first.Scalar() == key) return kv.second;
  }
  return std::nullopt;
}

std::string MapReader::full_key(std::string_view key) const {
  if (path_.empty()) return std::string(key);
  if (key.empty()) return path_;
  return path_ + "." + std::string(key);
}

int MapReader::line_of(std::string_view key) const {
  if (valid_ && !key.empty()) {
    for (const auto& kv : node_) {
      if (kv.first.IsScalar() && kv.first.Scalar() == key) return kv.first.Mark().line + 1;
    }
  }
  const int line = node_.Mark().line;
  return line >= 0 ? line + 1 : 0;
}

void MapReader::error(std::string_view key, std::string message) const {
  errors_->add({file_, line_of(key), full_key(key), std::move(message)});
}

std::optional<MapReader> MapReader::map(std::string_view key, bool required) {
  const std::optional<YAML::Node> value = find(key);
  if (!value) {
    if (required) error(key, "is required (a map)");
    return std::nullopt;
  }
  if (!value->IsMap() && !value->IsNull()) {
    error(key, "must be a map of key: value pairs");
    return std::nullopt;
  }
  return MapReader(*value, file_, full_key(key), *errors_);
}

std::vector<YAML::Node> MapReader::sequence(std::string_view key, bool required) {
  const std::optional<YAML::Node> value = find(key);
  std::vector<YAML::Node> out;
  if (!value) {
    if (required) error(key, "is required (a list)");
    return out;
  }
  if (value->IsNull()) return out;
  if (!value->IsSequence()) {
    error(key, "must be a list");
    return out;
  }
  for (const auto& item : *value) out.push_back(item);
  return out;
}

std::optional<MapReader> MapReader::element(const YAML::Node& node, std::size_t index,
                                            std::string_view sequence_key) {
  const std::string path = full_key(sequence_key) + "[" + std::to_string(index) + "]";
  if (!node.IsMap()) {
    const int line = node.Mark().line;
    errors_->add({file_, line >= 0 ? line + 1 : 0, path, "must be a map of key: value pairs"});
    return std::nullopt;
  }
  return MapReader(node, file_, path, *errors_);
}

void MapReader::finish() {
  if (finished_ || !valid_) return;
  finished_ = true;
  for (const auto& kv : node_) {
    const std::string key = kv.first.IsScalar() ? kv.first.Scalar() : std::string("<non-scalar>");
    if (seen_.find(key) == seen_.end()) {
      errors_->add({file_, kv.first.Mark().line + 1, full_key(key), "is not a known key"});
    }
  }
}

namespace {

// Counts a stream's documents without building them. yaml-cpp 0.7's LoadAll never returns on
// some malformed input (a lone ',' at the top level): its parser then reports one empty document
// after another at the same place, forever. A document that starts where the previous one did is
// that case, and ends the count.
class DocumentStarts final : public YAML::EventHandler {
 public:
  void OnDocumentStart(const YAML::Mark& mark) override { start = mark; }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark& /*mark*/, YAML::anchor_t /*anchor*/) override {}
  void OnAlias(const YAML::Mark& /*mark*/, YAML::anchor_t /*anchor*/) override {}
  void OnScalar(const YAML::Mark& /*mark*/, const std::string& /*tag*/, YAML::anchor_t /*anchor*/,
                const std::string& /*value*/) override {}
  void OnSequenceStart(const YAML::Mark& /*mark*/, const std::string& /*tag*/,
                       YAML::anchor_t /*anchor*/, YAML::EmitterStyle::value /*style*/) override {}
  void OnSequenceEnd() override {}
  void OnMapStart(const YAML::Mark& /*mark*/, const std::string& /*tag*/, YAML::anchor_t /*anchor*/,
                  YAML::EmitterStyle::value /*style*/) override {}
  void OnMapEnd() override {}
  YAML::Mark start;
};

struct DocumentCount {
  std::size_t documents = 0;
  int second_line = -1;  // where the second document starts (0-based), -1 none
  bool stuck = false;    // the parser stopped making progress
  int stuck_line = -1;
};

// Throws YAML::Exception on a syntax error, as the loaders do.
DocumentCount count_documents(const std::string& text) {
  std::istringstream in(text);
  YAML::Parser parser(in);
  DocumentStarts starts;
  DocumentCount count;
  int previous_pos = -1;
  // Every document holds at least one character, so no stream of n bytes holds more than n + 1.
  while (count.documents <= text.size() && parser.HandleNextDocument(starts)) {
    if (starts.start.pos == previous_pos) {
      count.stuck = true;
      count.stuck_line = starts.start.line;
      return count;
    }
    previous_pos = starts.start.pos;
    if (++count.documents == 2) count.second_line = starts.start.line;
  }
  return count;
}

// The walk of a document: counts the values it visits (an alias each time it is used) and stops
// at the first bound passed.
struct DocumentWalk {
  std::size_t nodes = 0;
  bool too_big = false;
};

// Duplicate keys anywhere below `node` (yaml-cpp keeps both pairs and answers lookups with the
// first, so a second `baud:` would be silently ignored); nesting and size bounded, so no reader
// walks a document without end.
void check_duplicate_keys(const YAML::Node& node, const std::string& path, ConfigErrors& errors,
                          int depth, DocumentWalk& walk) {
  if (walk.too_big) return;
  if (++walk.nodes > kMaxConfigNodes) {
    walk.too_big = true;
    errors.add({path, 0, "",
                "expands to more than " + std::to_string(kMaxConfigNodes) +
                    " values (anchors and aliases counted each time they are used); a config "
                    "file may have at most that many"});
    return;
  }
  if (depth > kMaxConfigDepth) {
    walk.too_big = true;
    const int line = node.Mark().line;
    errors.add({path, line >= 0 ? line + 1 : 0, "",
                "nests maps and lists deeper than " + std::to_string(kMaxConfigDepth) +
                    " levels; a config file may not"});
    return;
  }
  if (node.IsMap()) {
    std::map<std::string, int, std::less<>> first_line;
    for (const auto& kv : node) {
      if (kv.first.IsScalar()) {
        const int line = kv.first.Mark().line + 1;
        const auto [it, inserted] = first_line.emplace(kv.first.Scalar(), line);
        if (!inserted) {
          errors.add({path, line, kv.first.Scalar(),
                      "is a duplicate key (first at line " + std::to_string(it->second) + ")"});
        }
      }
      check_duplicate_keys(kv.second, path, errors, depth + 1, walk);
      if (walk.too_big) return;
    }
  } else if (node.IsSequence()) {
    for (const auto& item : node) {
      check_duplicate_keys(item, path, errors, depth + 1, walk);
      if (walk.too_big) return;
    }
  }
}

}  // namespace

bool is_decimal_integer(std::string_view text) {
  std::size_t i = 0;
  if (!text.empty() && (text[0] == '-' || text[0] == '+')) i = 1;
  if (i >= text.size()) return false;
  if (text[i] == '0' && text.size() > i + 1) return false;  // 0115200 is not octal here
  for (; i < text.size(); ++i) {
    if (text[i] < '0' || text[i] > '9') return false;
  }
  return true;
}

std::optional<YAML::Node> load_yaml_file(const std::string& path, ConfigErrors& errors,
                                         std::uintmax_t max_bytes) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    errors.add({path, 0, "", "cannot be read: no such file"});
    return std::nullopt;
  }
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) {
    errors.add({path, 0, "", "cannot be read: " + ec.message()});
    return std::nullopt;
  }
  if (size > max_bytes) {
    errors.add({path, 0, "",
                "is " + std::to_string(size) + " bytes, more than the " +
                    std::to_string(max_bytes) + " a config file may have"});
    return std::nullopt;
  }
  std::ifstream in(path);
  if (!in) {
    errors.add({path, 0, "", "cannot be opened for reading"});
    return std::nullopt;
  }
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  YAML::Node doc;
  try {
    const DocumentCount count = count_documents(text);
    if (count.stuck) {
      errors.add({path, count.stuck_line + 1, "",
                  "YAML syntax error: the parser cannot go on from here (a stray ',' or the "
                  "like)"});
      return std::nullopt;
    }
    if (count.documents > 1) {
      errors.add({path, count.second_line + 1, "",
                  "holds " + std::to_string(count.documents) +
                      " YAML documents; exactly one is expected (a second '---' or '...')"});
      return std::nullopt;
    }
    if (count.documents == 1) doc = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    errors.add({path, e.mark.line + 1, "", "YAML syntax error: " + e.msg});
    return std::nullopt;
  }
  if (!doc || doc.IsNull()) {
    errors.add({path, 0, "", "is empty: one YAML document (a map) is expected"});
    return std::nullopt;
  }
  const std::size_t before = errors.size();
  DocumentWalk walk;
  check_duplicate_keys(doc, path, errors, 0, walk);
  if (errors.size() != before) return std::nullopt;
  return doc;
}

}  // namespace coxswain::config
