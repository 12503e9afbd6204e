// SPDX-License-Identifier: Apache-2.0
// The notify protocol against a real datagram socket set as NOTIFY_SOCKET, as systemd does it.
#include "coxswain/app/systemd_notify.hpp"

#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <array>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace coxswain::app {
namespace {

class NotifySocket {
 public:
  NotifySocket() {
    path_ = (std::filesystem::temp_directory_path() /
             ("coxswain_notify_" + std::to_string(::getpid()) + ".sock"))
                .string();
    ::unlink(path_.c_str());
    fd_ = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    path_.copy(addr.sun_path, sizeof(addr.sun_path) - 1);
    bound_ = ::bind(fd_, reinterpret_cast<const sockaddr*>(&addr), sizeof(addr)) == 0;
    timeval tv{2, 0};
    ::setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof(tv));
    ::setenv("NOTIFY_SOCKET", path_.c_str(), 1);
  }
  ~NotifySocket() {
    ::unsetenv("NOTIFY_SOCKET");
    ::close(fd_);
    ::unlink(path_.c_str());
  }
  NotifySocket(const NotifySocket&) = delete;
  NotifySocket& operator=(const NotifySocket&) = delete;
  [[nodiscard]] bool bound() const { return bound_; }
  std::string receive() {
    std::array<char, 512> buf{};
    const ssize_t n = ::recv(fd_, buf.data(), buf.size(), 0);
    return n > 0 ? std::string(buf.data(), static_cast<std::size_t>(n)) : std::string();
  }

 private:
  std::string path_;
  int fd_ = -1;
  bool bound_ = false;
};

TEST(SystemdNotifier, SendsReadyStatusWatchdogStopping) {
  NotifySocket socket;
  ASSERT_TRUE(socket.bound());
  const SystemdNotifier notifier;
  ASSERT_TRUE(notifier.enabled());
  EXPECT_TRUE(notifier.ready());
  EXPECT_EQ(socket.receive(), "READY=1");
  EXPECT_TRUE(notifier.status("hopping: lidar=absent\nimu=absent"));
  EXPECT_EQ(socket.receive(), "STATUS=hopping: lidar=absent imu=absent");
  EXPECT_TRUE(notifier.watchdog());
  EXPECT_EQ(socket.receive(), "WATCHDOG=1");
  EXPECT_TRUE(notifier.stopping());
  EXPECT_EQ(socket.receive(), "STOPPING=1");
}

TEST(SystemdNotifier, WatchdogIntervalFromEnvironment) {
  ::setenv("WATCHDOG_USEC", "2000000", 1);
  ::setenv("WATCHDOG_PID", std::to_string(::getpid()).c_str(), 1);
  const SystemdNotifier notifier;
  EXPECT_EQ(notifier.watchdog_interval_ns(), 2'000'000'000);
  ::unsetenv("WATCHDOG_USEC");
  ::unsetenv("WATCHDOG_PID");
}

TEST(SystemdNotifier, NoSocketMeansNoOp) {
  ::unsetenv("NOTIFY_SOCKET");
  const SystemdNotifier notifier;
  EXPECT_FALSE(notifier.enabled());
  EXPECT_FALSE(notifier.ready());
  EXPECT_EQ(notifier.watchdog_interval_ns(), 0);
}

}  // namespace
}  // namespace coxswain::app
