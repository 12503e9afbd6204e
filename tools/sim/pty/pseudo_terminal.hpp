// SPDX-License-Identifier: Apache-2.0
#pragma once
// A pseudo-terminal standing in for a USB serial device: the emulator owns the master side, the
// host under test opens the slave (directly or through a udev-like symlink such as /dev/ttyGPS).
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>

namespace coxswain::sim::pty {

/// One pty pair in raw mode. The master fd is non-blocking. An optional symlink at `link_path`
/// points to the slave, as udev would name a real device; unplug() removes it and closes the
/// master, so the host's open port then fails its reads (EOF/EIO) exactly as on a USB unplug.
///
/// Thread-safety: none; one owner (EmulatorHost's thread, or a test) uses it.
class PseudoTerminal {
 public:
  /// Opens a pty pair; creates (or atomically replaces) the symlink when `link_path` is not
  /// empty. Throws std::system_error when the system refuses.
  explicit PseudoTerminal(std::filesystem::path link_path = {});
  ~PseudoTerminal();
  PseudoTerminal(const PseudoTerminal&) = delete;
  PseudoTerminal& operator=(const PseudoTerminal&) = delete;

  /// The slave's name (/dev/pts/N).
  [[nodiscard]] const std::string& slave_name() const { return slave_name_; }
  /// The symlink path, empty when none was asked for.
  [[nodiscard]] const std::filesystem::path& link_path() const { return link_path_; }
  /// What the host should open: the symlink if any, else the slave's name.
  [[nodiscard]] std::string device_path() const;
  [[nodiscard]] bool plugged() const { return master_fd_ >= 0; }
  [[nodiscard]] int master_fd() const { return master_fd_; }

  /// Removes the symlink (if it still points to this slave) and closes both of our fds.
  /// Idempotent.
  void unplug();

  /// Reads what the host wrote; never blocks. Returns the number of bytes read (0 when nothing is
  /// waiting or when unplugged). Throws std::system_error on an unexpected error.
  std::size_t read(std::span<std::uint8_t> out);
  /// Writes towards the host; never blocks. Returns how many bytes the pty accepted (fewer than
  /// asked, possibly 0, when its buffer is full; 0 when unplugged).
  std::size_t write(std::span<const std::uint8_t> bytes);

 private:
  std::filesystem::path link_path_;
  std::string slave_name_;
  int master_fd_ = -1;
  // Our own fd on the slave, held while plugged. Linux reports a hangup (EIO on read, POLLHUP)
  // on the master whenever no fd on the slave is open, so without it the emulator would see
  // spurious hangups before the host opens the port and between a host's close and reopen; it
  // also keeps the raw termios settings in place across host opens. We never read from it.
  int slave_fd_ = -1;
};

}  // namespace coxswain::sim::pty
