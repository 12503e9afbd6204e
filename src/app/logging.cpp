// SPDX-License-Identifier: Apache-2.0
#include "coxswain/app/logging.hpp"

#include <spdlog/async.h>
#include <spdlog/sinks/base_sink.h>
#include <spdlog/sinks/dist_sink.h>
#include <spdlog/sinks/rotating_file_sink.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <mutex>
#include <utility>
#include <vector>

namespace coxswain::app {
namespace {

// Every sink of the default logger behind one repeat limiter: the console, the file and the tap.
class RepeatLimitSink final : public spdlog::sinks::base_sink<std::mutex> {
 public:
  RepeatLimitSink(std::vector<spdlog::sink_ptr> sinks, std::chrono::nanoseconds window)
      : sinks_(std::move(sinks)), limiter_(window) {}

  /// Reports every count still open (at shutdown, once the logging thread has stopped).
  void drain() {
    const std::lock_guard<std::mutex> lock(mutex_);
    const auto now = spdlog::log_clock::now();
    limiter_.expire_all([&](int level, std::uint64_t count, const std::string& last) {
      report(now, "coxswain", level, count, last);
    });
    for (const auto& s : sinks_) s->flush();
  }

 protected:
  void sink_it_(const spdlog::details::log_msg& msg) override {
    report_expired(msg.time, msg.logger_name);
    if (msg.level >= kRepeatLimitLevel &&
        !limiter_.admit(msg.level, std::string_view(msg.payload.data(), msg.payload.size()),
                        msg.time)) {
      return;
    }
    forward(msg);
  }
  // The pattern is each destination's, as a dist_sink passes it on.
  void set_pattern_(const std::string& pattern) override {
    set_formatter_(std::make_unique<spdlog::pattern_formatter>(pattern));
  }
  void set_formatter_(std::unique_ptr<spdlog::formatter> formatter) override {
    formatter_ = std::move(formatter);
    for (const auto& s : sinks_) s->set_formatter(formatter_->clone());
  }
  void flush_() override {
    report_expired(spdlog::log_clock::now(), "coxswain");
    for (const auto& s : sinks_) s->flush();
  }

 private:
  void forward(const spdlog::details::log_msg& msg) {
    for (const auto& s : sinks_) {
      if (s->should_log(msg.level)) s->log(msg);
    }
  }
  void report(spdlog::log_clock::time_point now, spdlog::string_view_t logger_name, int level,
              std::uint64_t count, const std::string& last) {
    const std::string text =
        "... " + std::to_string(count) + " similar suppressed (last: " + last + ")";
    const spdlog::details::log_msg summary(now, spdlog::source_loc{}, logger_name,
                                           static_cast<spdlog::level::level_enum>(level), text);
    forward(summary);
  }
  void report_expired(spdlog::log_clock::time_point now, spdlog::string_view_t logger_name) {
    limiter_.expire(now, [&](int level, std::uint64_t count, const std::string& last) {
      report(now, logger_name, level, count, last);
    });
  }

  std::vector<spdlog::sink_ptr> sinks_;
  RepeatLimiter limiter_;
};

// The tap and the limiter of the installed logger (null when none is installed).
std::mutex g_tap_mutex;
std::shared_ptr<spdlog::sinks::dist_sink_mt> g_tap;
std::shared_ptr<RepeatLimitSink> g_limiter;

std::shared_ptr<spdlog::sinks::dist_sink_mt> tap() {
  const std::lock_guard<std::mutex> lock(g_tap_mutex);
  return g_tap;
}

}  // namespace

RepeatLimiter::RepeatLimiter(std::chrono::nanoseconds window, std::size_t max_keys)
    : window_(window), max_keys_(max_keys) {}

std::string RepeatLimiter::key_of(std::string_view text) {
  std::string key;
  key.reserve(text.size());
  bool in_number = false;
  for (const char c : text) {
    const bool numeric = (c >= '0' && c <= '9') || c == '.';
    if (numeric) {
      if (!in_number) key += '#';
    } else {
      key += c;
    }
    in_number = numeric;
  }
  return key;
}

bool RepeatLimiter::admit(int level, std::string_view text, Clock::time_point at) {
  // One line per state change is the log's promise (and what devices mode reads back).
  if (text.starts_with("device ") || text.starts_with("mission: ")) return true;
  auto key = std::make_pair(level, key_of(text));
  const auto it = entries_.find(key);
  if (it != entries_.end() && at - it->second.opened < window_) {
    ++it->second.suppressed;
    it->second.last_text.assign(text);
    return false;
  }
  if (it != entries_.end()) {
    it->second = Entry{at, 0, {}};  // its window ended with nothing counted: a new one opens
    return true;
  }
  if (entries_.size() >= max_keys_) return true;  // bounded: past the cap, lines pass
  entries_.emplace(std::move(key), Entry{at, 0, {}});
  return true;
}

void RepeatLimiter::expire(
    Clock::time_point now,
    const std::function<void(int, std::uint64_t, const std::string&)>& report) {
  for (auto it = entries_.begin(); it != entries_.end();) {
    if (now - it->second.opened < window_) {
      ++it;
      continue;
    }
    if (it->second.suppressed > 0)
      report(it->first.first, it->second.suppressed, it->second.last_text);
    it = entries_.erase(it);
  }
}

void RepeatLimiter::expire_all(
    const std::function<void(int, std::uint64_t, const std::string&)>& report) {
  for (const auto& [key, entry] : entries_) {
    if (entry.suppressed > 0) report(key.first, entry.suppressed, entry.last_text);
  }
  entries_.clear();
}

std::optional<int> parse_log_level(const std::string& text) {
  const auto level = spdlog::level::from_str(text);
  if (level == spdlog::level::off && text != "off") return std::nullopt;
  return static_cast<int>(level);
}

void setup_logging(const std::optional<std::filesystem::path>& log_file, int level,
                   const LogFileLimits& limits, std::chrono::nanoseconds repeat_window) {
  spdlog::init_thread_pool(8192, 1);
  std::vector<spdlog::sink_ptr> sinks;
  sinks.push_back(std::make_shared<spdlog::sinks::stderr_color_sink_mt>());
  if (log_file) {
    sinks.push_back(std::make_shared<spdlog::sinks::rotating_file_sink_mt>(
        log_file->string(), limits.max_bytes, limits.files));
  }
  // Empty until attach_log_sink(); its mutex is taken by the logging thread and by attach/detach
  // only, never by the threads that log.
  auto t = std::make_shared<spdlog::sinks::dist_sink_mt>();
  sinks.push_back(t);
  auto limited = std::make_shared<RepeatLimitSink>(std::move(sinks), repeat_window);
  auto logger = std::make_shared<spdlog::async_logger>(
      "coxswain", limited, spdlog::thread_pool(), spdlog::async_overflow_policy::overrun_oldest);
  logger->set_level(static_cast<spdlog::level::level_enum>(level));
  logger->set_pattern("%Y-%m-%d %H:%M:%S.%e %^%-5l%$ %v");
  logger->flush_on(spdlog::level::warn);
  spdlog::set_default_logger(logger);
  spdlog::flush_every(std::chrono::seconds(1));
  const std::lock_guard<std::mutex> lock(g_tap_mutex);
  g_tap = t;
  g_limiter = limited;
}

bool attach_log_sink(const std::shared_ptr<spdlog::sinks::sink>& sink, int level) {
  const auto t = tap();
  if (!t) return false;
  sink->set_level(static_cast<spdlog::level::level_enum>(level));
  t->add_sink(sink);
  return true;
}

void detach_log_sink(const std::shared_ptr<spdlog::sinks::sink>& sink) {
  if (const auto t = tap()) t->remove_sink(sink);
}

void shutdown_logging() {
  if (auto logger = spdlog::default_logger()) logger->flush();
  spdlog::shutdown();  // joins the logging thread: every queued line has reached the sinks
  std::shared_ptr<RepeatLimitSink> limiter;
  {
    const std::lock_guard<std::mutex> lock(g_tap_mutex);
    limiter = std::move(g_limiter);
    g_tap.reset();
  }
  if (limiter) limiter->drain();
}

}  // namespace coxswain::app
