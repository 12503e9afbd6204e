// SPDX-License-Identifier: Apache-2.0
#include "sim/devices_mode/daemon_process.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <iostream>
#include <regex>
#include <system_error>

#include "coxswain/core/clock.hpp"

namespace coxswain::sim::devices_mode {
namespace {

// The daemon's log patterns (src/app: health_reporter.cpp, core_host.cpp, daemon.cpp). Lines
// are rare (state changes, one counters line per device every 10 s), so std::regex is cheap
// enough here.
const std::regex& device_re() {
  static const std::regex re(R"(device (\w+): (\w+) \()");
  return re;
}
const std::regex& mission_re() {
  static const std::regex re(R"(mission: (\S+) -> (\S+): (.*)$)");
  return re;
}
const std::regex& counters_re() {
  static const std::regex re(R"(counters (\w+): state=\S+ .* rate=([0-9.]+)Hz)");
  return re;
}
const std::regex& tick_re() {
  static const std::regex re(
      R"(tick: \d+ ticks, duration min \S+ mean \S+ p99 (\S+) max (\S+) ms, .* overruns (\d+))");
  return re;
}
const std::regex& stopping_re() {
  static const std::regex re(
      R"(stopping.*: commanded neutral actuators; (\d+) ticks in \S+ s, (\d+) overruns)");
  return re;
}

}  // namespace

void parse_daemon_line(const std::string& line, core::TimeNs stamp_ns, DaemonReport& report) {
  std::smatch m;
  if (!report.started && line.find(") starting") != std::string::npos) {
    report.started = true;
  } else if (line.find("mission: ") != std::string::npos &&
             std::regex_search(line, m, mission_re())) {
    report.transitions.push_back({stamp_ns, m[1].str(), m[2].str(), m[3].str()});
  } else if (line.find("mission finished after") != std::string::npos) {
    report.finished = true;
  } else if (line.find("counters ") != std::string::npos &&
             std::regex_search(line, m, counters_re())) {
    report.device_rate_hz[m[1].str()] = std::stod(m[2].str());
  } else if (line.find("device ") != std::string::npos && std::regex_search(line, m, device_re())) {
    report.device_state[m[1].str()] = m[2].str();
  } else if (line.find("tick: ") != std::string::npos && std::regex_search(line, m, tick_re())) {
    report.worst_tick_p99_ms = std::max(report.worst_tick_p99_ms, std::stod(m[1].str()));
    report.worst_tick_max_ms = std::max(report.worst_tick_max_ms, std::stod(m[2].str()));
    report.window_overruns += std::stoull(m[3].str());
  } else if (line.find("stopping") != std::string::npos &&
             std::regex_search(line, m, stopping_re())) {
    report.total_ticks = std::stoull(m[1].str());
    report.total_overruns = std::stoull(m[2].str());
  }
}

DaemonProcess::DaemonProcess(const std::vector<std::string>& argv,
                             const std::filesystem::path& log_copy, bool echo)
    : echo_(echo) {
  if (!log_copy.empty()) log_copy_.open(log_copy);
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) {
    throw std::system_error(errno, std::generic_category(), "pipe2");
  }
  // Everything the child needs is built before fork(): only async-signal-safe calls after it.
  std::vector<char*> args;
  args.reserve(argv.size() + 1);
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) {
    const int err = errno;
    ::close(fds[0]);
    ::close(fds[1]);
    throw std::system_error(err, std::generic_category(), "fork");
  }
  if (pid == 0) {
    ::prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (::getppid() != parent) ::_exit(127);  // the simulator already died
    ::dup2(fds[1], STDOUT_FILENO);
    ::dup2(fds[1], STDERR_FILENO);
    sigset_t none;
    sigemptyset(&none);
    ::sigprocmask(SIG_SETMASK, &none, nullptr);
    ::signal(SIGINT, SIG_DFL);
    ::signal(SIGTERM, SIG_DFL);
    // Its own process group: a Ctrl-C at the terminal reaches the simulator only, which then
    // stops the daemon in order (SIGTERM) and waits for it.
    ::setpgid(0, 0);
    ::execv(args[0], args.data());
    ::_exit(127);
  }
  ::close(fds[1]);
  pid_ = pid;
  reader_ = std::thread([this, fd = fds[0]] { read_loop(fd); });
}

DaemonProcess::~DaemonProcess() {
  (void)stop();
  if (reader_.joinable()) reader_.join();
}

void DaemonProcess::read_loop(int fd) {
  std::string partial;
  char buf[4096];
  for (;;) {
    const ssize_t n = ::read(fd, buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    const core::TimeNs now = core::SteadyClock().now_ns();
    partial.append(buf, static_cast<std::size_t>(n));
    std::size_t start = 0;
    for (std::size_t nl = partial.find('\n'); nl != std::string::npos;
         nl = partial.find('\n', start)) {
      std::string line = partial.substr(start, nl - start);
      start = nl + 1;
      if (echo_) std::cerr << "[coxswain] " << line << '\n';
      std::lock_guard<std::mutex> lock(mutex_);
      if (log_copy_.is_open()) log_copy_ << line << '\n';
      parse_daemon_line(line, now, report_);
      lines_.push_back({now, std::move(line)});
    }
    partial.erase(0, start);
    changed_.notify_all();
  }
  ::close(fd);
  std::lock_guard<std::mutex> lock(mutex_);
  if (log_copy_.is_open()) log_copy_.flush();
  closed_ = true;
  changed_.notify_all();
}

int DaemonProcess::stop(std::chrono::milliseconds grace) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (reaped_) return exit_status_;
  }
  if (pid_ <= 0) return 0;
  const auto deadline = std::chrono::steady_clock::now() + grace;
  // A daemon still loading its configuration would die of the signal's default action; once it
  // has said it is starting, it handles the signal and stops in order. The wait is bounded by
  // the same grace.
  {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait_until(lock, deadline, [this] { return report_.started || closed_; });
  }
  ::kill(pid_, SIGTERM);
  int status = 0;
  pid_t r = 0;
  while ((r = ::waitpid(pid_, &status, WNOHANG)) == 0 &&
         std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  if (r == 0) {
    ::kill(pid_, SIGKILL);
    r = ::waitpid(pid_, &status, 0);
  }
  int code = 0;
  if (r == pid_) {
    code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  }
  // The output ends with the process (nothing else holds the pipe's write end).
  {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait_for(lock, std::chrono::seconds(2), [this] { return closed_; });
    reaped_ = true;
    exit_status_ = code;
  }
  return code;
}

bool DaemonProcess::output_closed() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return closed_;
}

DaemonReport DaemonProcess::report() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return report_;
}

std::size_t DaemonProcess::line_count() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return lines_.size();
}

std::vector<LogLine> DaemonProcess::lines() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return lines_;
}

std::optional<std::pair<std::size_t, LogLine>> DaemonProcess::wait_for(
    std::size_t from, const std::function<bool(const std::string&)>& pred,
    std::chrono::milliseconds timeout) const {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  std::unique_lock<std::mutex> lock(mutex_);
  std::size_t next = from;
  for (;;) {
    for (; next < lines_.size(); ++next) {
      if (pred(lines_[next].text)) return std::make_pair(next, lines_[next]);
    }
    if (closed_) return std::nullopt;
    if (changed_.wait_until(lock, deadline) == std::cv_status::timeout && next >= lines_.size()) {
      return std::nullopt;
    }
  }
}

}  // namespace coxswain::sim::devices_mode
