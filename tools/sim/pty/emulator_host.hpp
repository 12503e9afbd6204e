// SPDX-License-Identifier: Apache-2.0
#pragma once
// Runs a pure device emulator core on a pseudo-terminal in real time, so the unmodified daemon
// (or a transport test) talks to it as to a USB serial device, with faults injected into the
// byte stream: unplug/replug, silence, garbage bursts and bit corruption.
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "coxswain/core/time.hpp"
#include "sim/devices/device_emulator.hpp"
#include "sim/pty/pseudo_terminal.hpp"
#include "sim/rng/rng.hpp"

namespace coxswain::sim::pty {

/// What the host injected and moved, since construction. Bytes are counted at the pty.
struct HostCounters {
  std::uint64_t bytes_from_host = 0;  // read from the pty and handed to receive()
  std::uint64_t device_bytes = 0;     // produced by the emulator's poll()
  std::uint64_t bytes_to_host = 0;    // accepted by the pty (device bytes + garbage)
  std::uint64_t silenced_bytes = 0;   // produced while silent, not sent
  std::uint64_t unplugged_bytes = 0;  // produced while unplugged, not sent
  std::uint64_t overflow_bytes = 0;   // dropped because nobody read the pty (buffer full)
  std::uint64_t garbage_bursts = 0;
  std::uint64_t garbage_bytes = 0;  // random bytes inserted (included in bytes_to_host)
  std::uint64_t bits_flipped = 0;   // corrupted device bytes (one bit each)
  std::uint64_t unplugs = 0;
  std::uint64_t replugs = 0;
};

/// Owns a PseudoTerminal and a thread that, every tick (steady clock, absolute deadlines), reads
/// what the host wrote into `device.receive()`, polls `device.poll(now)` and writes the output,
/// after fault injection, to the pty. Output the pty does not accept yet (EAGAIN, partial
/// writes) waits in a bounded buffer; beyond `max_pending_bytes` the oldest is dropped, as a UART
/// with nobody listening loses bytes. While unplugged the device keeps running (its time keeps
/// flowing) but its output is discarded.
///
/// Time: the emulator sees steady-clock nanoseconds (core::SteadyClock's epoch).
/// Thread-safety: every public method may be called from any thread. The emulator itself is
/// touched by the host's thread; others reach it only inside `locked(f)`, which runs `f()` under
/// the host's lock between two service ticks (keep it short: feeding truth, reading stats).
class EmulatorHost {
 public:
  struct Options {
    std::filesystem::path link_path;            // udev-like symlink; empty = use /dev/pts/N
    core::TimeNs tick_ns = 2 * core::kNsPerMs;  // service period
    std::uint64_t seed = 1;                     // fault PRNG seed
    std::size_t max_pending_bytes = 64 * 1024;
  };

  /// Opens the pty and starts the thread. `device` must outlive the host. Throws
  /// std::system_error when the pty cannot be made.
  EmulatorHost(devices::DeviceEmulator& device, Options options);
  ~EmulatorHost();
  EmulatorHost(const EmulatorHost&) = delete;
  EmulatorHost& operator=(const EmulatorHost&) = delete;

  /// Stops the thread (prompt: woken at once): the device freezes, still plugged, so the host
  /// can drain what was sent. The destructor unplugs. Idempotent.
  void stop();

  /// The path the host should open (the symlink, or the current slave's name).
  [[nodiscard]] std::string device_path() const;
  /// The current slave's name ("" while unplugged).
  [[nodiscard]] std::string slave_name() const;

  /// USB unplug: the symlink disappears and the host's open port fails (EOF/EIO).
  void unplug();
  /// Plugs a fresh pty in (new /dev/pts/N, symlink re-pointed). No-op when plugged.
  void replug();
  [[nodiscard]] bool plugged() const;

  /// The device keeps producing but sends nothing (a dead sensor, a cut TX wire).
  void set_silent(bool silent);
  /// Before each chunk of device output, with `probability`, insert 1..max_burst_bytes random
  /// bytes. 0 disables.
  void set_garbage(double probability, std::size_t max_burst_bytes = 32);
  /// Each outgoing device byte has one random bit flipped with `probability`. 0 disables.
  void set_corruption(double bit_flip_probability);

  [[nodiscard]] HostCounters counters() const;

  /// Runs `f()` under the host's lock, between two service ticks: the only safe way for
  /// another thread to touch the emulator while the host runs.
  template <class F>
  decltype(auto) locked(F&& f) {
    std::lock_guard<std::mutex> lock(mutex_);
    return std::forward<F>(f)();
  }

 private:
  void run();
  void service(core::TimeNs now_ns);  // called with mutex_ held
  void enqueue(std::span<const std::uint8_t> bytes);
  void flush_pending();

  devices::DeviceEmulator& device_;
  const Options options_;

  mutable std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  std::unique_ptr<PseudoTerminal> pty_;  // null while unplugged
  bool silent_ = false;
  double garbage_probability_ = 0.0;
  std::size_t garbage_max_bytes_ = 32;
  double flip_probability_ = 0.0;
  Rng rng_;
  std::vector<std::uint8_t> pending_;  // accepted from the device, not yet by the pty
  std::vector<std::uint8_t> scratch_;
  std::vector<std::uint8_t> read_buf_;
  HostCounters counters_;

  std::thread thread_;  // last: starts after every member is ready
};

}  // namespace coxswain::sim::pty
