// SPDX-License-Identifier: Apache-2.0
#pragma once
// Each recorded message's fields, listed once. The same list writes, reads and documents both
// encodings: the legacy packed binary layouts (layouts.cpp) and protobuf (proto_codec.cpp), so no
// encoder, decoder or schema text can drift from another. Private to the record library.
//
// An Io visits fields in order:
//   field(name, value[, note])          one scalar or std::array of scalars
//   since(version, name, value)         a field added in a later binary layout version
//   elements(list, count, max, items, element)
//                                       a list of small records (`element(io, item)` visits one)
//   columns(list, count, max, items, element)
//                                       a long list of records of scalars; protobuf stores it as
//                                       one packed repeated field per member (column)
//   text(name, value, max_len) / text(name, setter)
//                                       a string (writers / readers)
// `Io::kReads` says whether the Io fills the message. In protobuf the field numbers are the
// positions in these lists: a field is only ever appended, never moved or removed.
#include <array>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <type_traits>

#include "coxswain/msg/actuator_command.hpp"
#include "coxswain/msg/arduino_status.hpp"
#include "coxswain/msg/camera_detections.hpp"
#include "coxswain/msg/device_health.hpp"
#include "coxswain/msg/gnss_fix.hpp"
#include "coxswain/msg/imu_sample.hpp"
#include "coxswain/msg/lidar_scan.hpp"
#include "coxswain/msg/operator_input.hpp"

namespace coxswain::record::detail {

// Arrays (fixed-size vectors such as a quaternion) are written element by element by every
// encoding.
template <class T>
struct IsStdArray : std::false_type {};
template <class T, std::size_t N>
struct IsStdArray<std::array<T, N>> : std::true_type {};

/// A list's names: its field (protobuf), its element type (protobuf), its count field and
/// whether that count is a field of its own listed before the list.
struct ListInfo {
  std::string_view field;
  std::string_view type;
  std::string_view count;
  bool count_written = false;
};

// Each `fields` takes `M&` (reading) or `const M&` (writing and describing).
template <class Io, class M>
requires std::same_as<std::remove_const_t<M>, msg::GnssFix>
void fields(Io& io, M& m) {
  io.field("stamp_ns", m.stamp_ns);
  io.field("source", m.source);
  io.field("fix_type", m.fix_type);
  io.field("fix_ok", m.fix_ok);
  io.field("diff_soln", m.diff_soln);
  io.field("rtk", m.rtk);
  io.field("lat_deg", m.lat_deg);
  io.field("lon_deg", m.lon_deg);
  io.field("height_msl_m", m.height_msl_m);
  io.field("h_acc_m", m.h_acc_m);
  io.field("v_acc_m", m.v_acc_m);
  io.field("hdop", m.hdop);
  io.field("satellites", m.satellites);
  io.field("velocity_valid", m.velocity_valid);
  io.field("vel_north_mps", m.vel_north_mps);
  io.field("vel_east_mps", m.vel_east_mps);
  io.field("vel_down_mps", m.vel_down_mps);
  io.field("ground_speed_mps", m.ground_speed_mps);
  io.field("course_deg", m.course_deg);
  io.field("utc_ns", m.utc_ns);
  io.field("itow_ms", m.itow_ms);
  io.since(2, "s_acc_mps", m.s_acc_mps);
}

template <class Io, class M>
requires std::same_as<std::remove_const_t<M>, msg::ImuSample>
void fields(Io& io, M& m) {
  io.field("stamp_ns", m.stamp_ns);
  io.field("roll_deg", m.roll_deg);
  io.field("pitch_deg", m.pitch_deg);
  io.field("yaw_magnetic_deg", m.yaw_magnetic_deg);
  io.field("heading_deg", m.heading_deg);
  io.field("accel_g", m.accel_g);
  io.field("gyro_dps", m.gyro_dps);
  io.field("mag_ut", m.mag_ut);
  io.field("temperature_c", m.temperature_c);
  io.field("has_inertial", m.has_inertial);
  io.field("sequence", m.sequence);
}

template <class Io, class M>
void lidar_header_fields(Io& io, M& m) {
  io.field("stamp_ns", m.stamp_ns);
  io.field("duration_ns", m.duration_ns);
  io.field("max_range_m", m.max_range_m);
  io.field("min_range_m", m.min_range_m);
  io.field("revolution", m.revolution);
  io.field("point_count", m.point_count);
}

template <class Io, class M>
requires std::same_as<std::remove_const_t<M>, msg::LidarScan>
void fields(Io& io, M& m) {
  lidar_header_fields(io, m);
  io.columns(ListInfo{"points", "Point", "point_count", true}, m.point_count,
             msg::LidarScan::kMaxPoints, m.points, [](auto& e, auto& p) {
               e.field("bearing_deg", p.bearing_deg, "body frame");
               e.field("range_m", p.range_m, "0 = no return");
               e.field("quality", p.quality);
               e.field("offset_us", p.offset_us);
             });
}

template <class Io, class M>
requires std::same_as<std::remove_const_t<M>, msg::CameraDetections>
void fields(Io& io, M& m) {
  io.field("stamp_ns", m.stamp_ns);
  io.field("frame_index", m.frame_index);
  io.field("image_width_px", m.image_width_px);
  io.field("image_height_px", m.image_height_px);
  io.elements(ListInfo{"detections", "Detection", "count", false}, m.count,
              msg::CameraDetections::kMaxDetections, m.detections, [](auto& e, auto& d) {
                e.field("colour", d.colour);
                e.field("shape", d.shape);
                e.field("bearing_deg", d.bearing_deg);
                e.field("center_x_px", d.center_x_px);
                e.field("center_y_px", d.center_y_px);
                e.field("width_px", d.width_px);
                e.field("height_px", d.height_px);
                e.field("area_px", d.area_px);
                e.field("score", d.score);
              });
}

template <class Io, class M>
requires std::same_as<std::remove_const_t<M>, msg::ArduinoStatus>
void fields(Io& io, M& m) {
  io.field("stamp_ns", m.stamp_ns);
  io.field("applied_pulse_us", m.applied_pulse_us);
  io.field("led", m.led);
  io.field("mode", m.mode);
  io.field("estop", m.estop);
  io.field("rc_present", m.rc_present);
  io.field("failsafe", m.failsafe);
  io.field("start_switch", m.start_switch);
  io.field("supply_v", m.supply_v);
  io.field("last_sequence_seen", m.last_sequence_seen);
}

template <class Io, class M>
requires std::same_as<std::remove_const_t<M>, msg::OperatorInput>
void fields(Io& io, M& m) {
  io.field("stamp_ns", m.stamp_ns);
  io.field("start_count", m.start_count);
  io.field("hold_count", m.hold_count);
  io.field("hold", m.hold);
  io.field("target_colour", m.target_colour);
  io.field("target_shape", m.target_shape);
}

template <class Io, class M>
requires std::same_as<std::remove_const_t<M>, msg::DeviceHealth>
void fields(Io& io, M& m) {
  io.field("stamp_ns", m.stamp_ns);
  io.field("device", m.device);
  io.field("state", m.state);
  io.field("bytes_received", m.bytes_received);
  io.field("frames_ok", m.frames_ok);
  io.field("checksum_errors", m.checksum_errors);
  io.field("framing_errors", m.framing_errors);
  io.field("dropped_frames", m.dropped_frames);
  io.field("reopen_count", m.reopen_count);
  io.field("last_frame_ns", m.last_frame_ns);
  io.field("rate_hz", m.rate_hz);
  if constexpr (Io::kReads) {
    io.text("detail", [&m](std::string_view s) { m.set_detail(s); });
  } else {
    io.text("detail", m.detail_text(), m.detail.size() - 1);
  }
}

template <class Io, class M>
requires std::same_as<std::remove_const_t<M>, msg::ActuatorCommand>
void fields(Io& io, M& m) {
  io.field("stamp_ns", m.stamp_ns);
  io.field("pulse_us", m.pulse_us);
  io.field("led", m.led);
  io.field("active", m.active);
}

}  // namespace coxswain::record::detail
