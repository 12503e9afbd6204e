// SPDX-License-Identifier: Apache-2.0
#pragma once
// Faults on demand for devices mode: `--fault DEVICE:KIND@T[+DURATION]`, so anyone can repeat a
// fault run. Each fault is applied to a serial device's emulator host at T seconds of run time
// and undone DURATION seconds later:
// - unplug:  the pty disappears (USB cable out) and comes back as a new pty;
// - reset:   a USB reset: the device is gone briefly, then back in its power-on state, sending
//            its start-up again (the daemon must configure it anew);
// - garbage: the device floods random bytes, every byte of its own output corrupted;
// - silence: the device keeps its port open but sends nothing (a dead sensor, a cut TX wire);
// - baud:    the device changed its baud rate: every byte arrives corrupted until it is back.
// What the daemon did about each fault is read from its log: when the mission held, when the
// device was running again, and when the mission resumed.
#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "coxswain/core/time.hpp"
#include "coxswain/msg/device_health.hpp"
#include "sim/devices_mode/daemon_process.hpp"

namespace coxswain::sim::devices_mode {

/// The devices on serial lines (pseudo-terminals in devices mode): the ones a fault can strike.
inline constexpr std::array<msg::DeviceId, 4> kSerialDevices{
    msg::DeviceId::kLidar, msg::DeviceId::kImu, msg::DeviceId::kGnss, msg::DeviceId::kArduino};

/// No later fault: a fault's log lines run to the end of the log.
inline constexpr core::TimeNs kNoLaterFault = std::numeric_limits<core::TimeNs>::max();

enum class FaultKind : std::uint8_t { kUnplug, kReset, kGarbage, kSilence, kBaud };

[[nodiscard]] std::string_view fault_kind_name(FaultKind kind);
/// How long a fault lasts when its spec gives no +DURATION.
[[nodiscard]] double default_fault_duration_s(FaultKind kind);

struct FaultSpec {
  msg::DeviceId device = msg::DeviceId::kLidar;
  FaultKind kind = FaultKind::kUnplug;
  double at_s = 0.0;        // run time (seconds of the world) when the fault begins
  double duration_s = 0.0;  // how long it lasts
};

/// Parses "DEVICE:KIND@T[+DURATION]" (e.g. "gnss:unplug@40+3"). DEVICE is a serial device
/// (lidar, imu, gnss, arduino). Throws std::invalid_argument naming what is wrong.
[[nodiscard]] FaultSpec parse_fault_spec(std::string_view spec);
/// The spec as it would be written on the command line ("gnss:unplug@40+3").
[[nodiscard]] std::string fault_spec_text(const FaultSpec& spec);

/// One fault of a run and what the daemon did about it (times in seconds of run time).
struct FaultRecord {
  FaultSpec spec;
  std::optional<double> began_s;  // applied
  std::optional<double> ended_s;  // undone
  core::TimeNs began_ns = 0;      // core::SteadyClock, as the daemon's log lines are stamped
  core::TimeNs ended_ns = 0;
  bool sailing_at_start = false;          // the mission was under way (not holding, not finished)
  std::optional<double> held_after_ms;    // from the start to the daemon's hold line
  std::optional<double> device_back_s;    // the device's "running" line after the end
  std::optional<double> resumed_after_s;  // from the end to the daemon's resume line
};

/// Fills the hold, device and resume times of `record` from the daemon's log lines (arrival
/// stamps: upper bounds) before `until_ns` (the start of the next fault, whose lines are its
/// own). A fault that never took the device out of "running" (garbage that the codec rode
/// through) has its device back at its end.
void observe_fault(const std::vector<LogLine>& lines, FaultRecord& record,
                   core::TimeNs until_ns = kNoLaterFault);

/// "gnss:unplug@40+3: held after 12 ms, device running 1.2 s after the end, resumed 1.4 s after
/// the end" (or what did not happen).
[[nodiscard]] std::string fault_summary_line(const FaultRecord& record);

/// True when the fault was recovered from: the device ran again and, if the mission held, it
/// resumed. (The mission holds only when its task in progress needs the device, so a fault
/// while sailing may be ridden through without a hold.)
[[nodiscard]] bool fault_recovered(const FaultRecord& record);

}  // namespace coxswain::sim::devices_mode
