// SPDX-License-Identifier: Apache-2.0
#include "coxswain/app/logging.hpp"

#include <spdlog/async.h>
#include <spdlog/sinks/basic_file_sink.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <vector>

namespace coxswain::app {

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
  auto logger = std::make_shared<spdlog::async_logger>(
      "coxswain", sinks.begin(), sinks.end(), spdlog::thread_pool(),
      spdlog::async_overflow_policy::overrun_oldest);
  logger->set_level(static_cast<spdlog::level::level_enum>(level));
  logger->set_pattern("%Y-%m-%d %H:%M:%S.%e %^%-5l%$ %v");
  logger->flush_on(spdlog::level::warn);
  spdlog::set_default_logger(logger);
  spdlog::flush_every(std::chrono::seconds(1));
}

void shutdown_logging() {
  if (auto logger = spdlog::default_logger()) logger->flush();
  spdlog::shutdown();
}

}  // namespace coxswain::app
