// SPDX-License-Identifier: Apache-2.0
#pragma once
// Messages with every field set to something other than its default, shared by the tests of
// both recording encodings.
#include <cstddef>
#include <string>

#include "coxswain/core/latest_store.hpp"
#include "coxswain/msg/actuator_command.hpp"
#include "coxswain/msg/device_health.hpp"
#include "coxswain/msg/gnss_fix.hpp"

namespace coxswain::record {

inline msg::GnssFix make_fix() {
  msg::GnssFix f;
  f.stamp_ns = 123456789;
  f.source = msg::GnssSource::kNmeaGga;
  f.fix_type = msg::FixType::k3D;
  f.fix_ok = true;
  f.rtk = msg::RtkSolution::kFixed;
  f.lat_deg = 35.123456789;
  f.lon_deg = 129.987654321;
  f.height_msl_m = 12.5;
  f.h_acc_m = 0.02;
  f.v_acc_m = 0.03;
  f.hdop = 0.7;
  f.satellites = 23;
  f.velocity_valid = true;
  f.vel_north_mps = 1.5;
  f.vel_east_mps = -0.5;
  f.ground_speed_mps = 1.58;
  f.course_deg = -18.4;
  f.utc_ns = 1700000000123456789;
  f.itow_ms = 345600000;
  f.s_acc_mps = 0.12;
  return f;
}

inline msg::DeviceHealth make_health(msg::DeviceId id) {
  msg::DeviceHealth h;
  h.stamp_ns = 99;
  h.device = id;
  h.state = msg::DeviceState::kRunning;
  h.bytes_received = 1U << 20U;
  h.frames_ok = 1000;
  h.checksum_errors = 3;
  h.framing_errors = 4;
  h.dropped_frames = 5;
  h.reopen_count = 2;
  h.last_frame_ns = 98;
  h.rate_hz = 10.0;
  h.set_detail(std::string(300, 'd'));  // longest detail the struct holds
  return h;
}

/// Every device's health slot filled (sequence = device number + 1).
inline void fill_health(core::Snapshot& snap) {
  for (std::size_t d = 0; d < msg::kDeviceCount; ++d) {
    snap.health[d] = {make_health(static_cast<msg::DeviceId>(d)), 3000, d + 1};
  }
}

/// An active command with both channels off neutral.
inline msg::ActuatorCommand make_command() {
  msg::ActuatorCommand cmd;
  cmd.pulse_us = {1650, 1420};
  cmd.active = true;
  cmd.led = msg::LedColour::kGreen;
  return cmd;
}

}  // namespace coxswain::record
