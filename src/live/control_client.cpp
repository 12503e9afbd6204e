// SPDX-License-Identifier: Apache-2.0
#include "coxswain/live/control_client.hpp"

#include <sys/socket.h>
#include <sys/time.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <nlohmann/json.hpp>
#include <system_error>

namespace coxswain::live {
namespace {

// Closes the descriptor on every path.
class Fd {
 public:
  explicit Fd(int fd) : fd_(fd) {}
  ~Fd() {
    if (fd_ >= 0) ::close(fd_);
  }
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
  [[nodiscard]] int get() const { return fd_; }

 private:
  int fd_;
};

}  // namespace

std::optional<std::string> send_control_command(const std::filesystem::path& socket,
                                                const std::string& line, std::string& error,
                                                double timeout_s) {
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  const std::string path = socket.string();
  if (path.empty() || path.size() >= sizeof(addr.sun_path)) {
    error = "bad control socket path '" + path + "'";
    return std::nullopt;
  }
  std::memcpy(addr.sun_path, path.c_str(), path.size() + 1);
  const Fd fd(::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0));
  if (fd.get() < 0) {
    error = std::string("socket: ") + std::strerror(errno);
    return std::nullopt;
  }
  timeval tv{};
  tv.tv_sec = static_cast<time_t>(timeout_s);
  tv.tv_usec = static_cast<suseconds_t>((timeout_s - static_cast<double>(tv.tv_sec)) * 1e6);
  ::setsockopt(fd.get(), SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof(tv));
  ::setsockopt(fd.get(), SOL_SOCKET, SO_SNDTIMEO, &tv, sizeof(tv));
  if (::connect(fd.get(), reinterpret_cast<const sockaddr*>(&addr), sizeof(addr)) != 0) {
    error = path + ": " + std::strerror(errno);
    return std::nullopt;
  }
  const std::string out = line + "\n";
  std::size_t sent = 0;
  while (sent < out.size()) {
    const ssize_t n = ::send(fd.get(), out.data() + sent, out.size() - sent, MSG_NOSIGNAL);
    if (n <= 0) {
      error = std::string("send: ") + std::strerror(errno);
      return std::nullopt;
    }
    sent += static_cast<std::size_t>(n);
  }
  std::string answer;
  char buf[4096];
  for (;;) {
    const ssize_t n = ::recv(fd.get(), buf, sizeof(buf), 0);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      error = n == 0 ? "the daemon closed the connection without an answer"
                     : std::string("no answer: ") + std::strerror(errno);
      return std::nullopt;
    }
    answer.append(buf, static_cast<std::size_t>(n));
    if (const auto nl = answer.find('\n'); nl != std::string::npos) {
      answer.resize(nl);
      return answer;
    }
  }
}

std::filesystem::path newest_run_socket(const std::filesystem::path& log_dir) {
  std::error_code ec;
  std::filesystem::path best;
  std::filesystem::file_time_type best_time{};
  for (const auto& entry : std::filesystem::directory_iterator(log_dir, ec)) {
    const std::filesystem::path candidate = entry.path() / "control.sock";
    std::error_code sec;
    if (!std::filesystem::is_socket(candidate, sec)) continue;
    const auto t = std::filesystem::last_write_time(candidate, sec);
    if (sec) continue;
    if (best.empty() || t > best_time) {
      best = candidate;
      best_time = t;
    }
  }
  return best;
}

bool answer_ok(const std::string& answer) {
  const nlohmann::json j = nlohmann::json::parse(answer, nullptr, false);
  if (!j.is_object()) return false;
  if (j.contains("ok")) return j["ok"].is_boolean() && j["ok"].get<bool>();
  return j.contains("state_path");
}

}  // namespace coxswain::live
