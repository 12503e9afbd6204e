// SPDX-License-Identifier: Apache-2.0
#include "coxswain/app/logging.hpp"

#include <spdlog/async.h>
#include <spdlog/sinks/basic_file_sink.h>
#include <spdlog/sinks/dist_sink.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <vector>

namespace coxswain::app {
namespace {

// The tap among the default logger's sinks, or null.
std::shared_ptr<spdlog::sinks::dist_sink_mt> tap() {
  const auto logger = spdlog::default_logger();
  if (!logger) return nullptr;
  for (const auto& s : logger->sinks()) {
    if (auto t = std::dynamic_pointer_cast<spdlog::sinks::dist_sink_mt>(s)) return t;
  }
  return nullptr;
}

}  // namespace

std::optional<int> parse_log_level(const std::string& text) {
  const auto level = spdlog::level::from_str(text);
  if (level == spdlog::level::off && text != "off") return std::nullopt;
  return static_cast<int>(level);
}

void setup_logging(const std::optional<std::filesystem::path>& log_file, int level) {
  spdlog::init_thread_pool(8192, 1);
  std::vector<spdlog::sink_ptr> sinks;
  sinks.push_back(std::make_shared<spdlog::sinks::stderr_color_sink_mt>());
  if (log_file) {
    sinks.push_back(std::make_shared<spdlog::sinks::basic_file_sink_mt>(log_file->string(), false));
  }
  // Empty until attach_log_sink(); its mutex is taken by the logging thread and by attach/detach
  // only, never by the threads that log.
  sinks.push_back(std::make_shared<spdlog::sinks::dist_sink_mt>());
  auto logger = std::make_shared<spdlog::async_logger>(
      "coxswain", sinks.begin(), sinks.end(), spdlog::thread_pool(),
      spdlog::async_overflow_policy::overrun_oldest);
  logger->set_level(static_cast<spdlog::level::level_enum>(level));
  logger->set_pattern("%Y-%m-%d %H:%M:%S.%e %^%-5l%$ %v");
  logger->flush_on(spdlog::level::warn);
  spdlog::set_default_logger(logger);
  spdlog::flush_every(std::chrono::seconds(1));
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
  spdlog::shutdown();
}

}  // namespace coxswain::app
