// SPDX-License-Identifier: Apache-2.0
#include "sim/pty/pseudo_terminal.hpp"

#include <fcntl.h>
#include <pty.h>
#include <termios.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <system_error>

namespace coxswain::sim::pty {
namespace {

[[noreturn]] void throw_errno(const std::string& what) {
  throw std::system_error(errno, std::generic_category(), what);
}

}  // namespace

PseudoTerminal::PseudoTerminal(std::filesystem::path link_path) : link_path_(std::move(link_path)) {
  std::array<char, 128> name{};
  termios raw{};
  cfmakeraw(&raw);
  if (openpty(&master_fd_, &slave_fd_, name.data(), &raw, nullptr) != 0) {
    throw_errno("openpty");
  }
  slave_name_ = name.data();
  const int flags = fcntl(master_fd_, F_GETFL);
  if (flags < 0 || fcntl(master_fd_, F_SETFL, flags | O_NONBLOCK) != 0 ||
      fcntl(master_fd_, F_SETFD, FD_CLOEXEC) != 0 || fcntl(slave_fd_, F_SETFD, FD_CLOEXEC) != 0) {
    const int saved = errno;
    unplug();
    throw std::system_error(saved, std::generic_category(), "pty fcntl");
  }
  if (!link_path_.empty()) {
    // Atomic re-point: make the new link beside the old one, then rename over it, so a host
    // polling the path never sees it missing while we replug.
    std::filesystem::path tmp = link_path_;
    tmp += ".tmp" + std::to_string(::getpid()) + "." + std::to_string(master_fd_);
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    std::filesystem::create_symlink(slave_name_, tmp, ec);
    if (!ec) std::filesystem::rename(tmp, link_path_, ec);
    if (ec) {
      std::filesystem::remove(tmp);
      unplug();
      throw std::system_error(ec, "symlink " + link_path_.string());
    }
  }
}

PseudoTerminal::~PseudoTerminal() { unplug(); }

std::string PseudoTerminal::device_path() const {
  return link_path_.empty() ? slave_name_ : link_path_.string();
}

void PseudoTerminal::unplug() {
  if (!link_path_.empty() && master_fd_ >= 0) {
    std::error_code ec;
    // Only our own link: a newer PseudoTerminal may already have re-pointed the path.
    if (std::filesystem::read_symlink(link_path_, ec) == slave_name_ && !ec) {
      std::filesystem::remove(link_path_, ec);
    }
  }
  if (slave_fd_ >= 0) {
    ::close(slave_fd_);
    slave_fd_ = -1;
  }
  if (master_fd_ >= 0) {
    ::close(master_fd_);
    master_fd_ = -1;
  }
}

std::size_t PseudoTerminal::read(std::span<std::uint8_t> out) {
  if (master_fd_ < 0 || out.empty()) return 0;
  for (;;) {
    const ssize_t n = ::read(master_fd_, out.data(), out.size());
    if (n >= 0) return static_cast<std::size_t>(n);
    if (errno == EINTR) continue;
    // EIO: no fd open on the slave, which cannot happen while we hold ours; treat as empty.
    if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EIO) return 0;
    throw_errno("pty read");
  }
}

std::size_t PseudoTerminal::write(std::span<const std::uint8_t> bytes) {
  if (master_fd_ < 0 || bytes.empty()) return 0;
  for (;;) {
    const ssize_t n = ::write(master_fd_, bytes.data(), bytes.size());
    if (n >= 0) return static_cast<std::size_t>(n);
    if (errno == EINTR) continue;
    if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EIO) return 0;
    throw_errno("pty write");
  }
}

}  // namespace coxswain::sim::pty
