// SPDX-License-Identifier: Apache-2.0
#include "coxswain/record/layouts.hpp"

namespace coxswain::record {
namespace {

template <class E>
void put_enum(ByteWriter& w, E e) {
  w.u8(static_cast<std::uint8_t>(e));
}
template <class E>
E get_enum(ByteReader& r) {
  return static_cast<E>(r.u8());
}

template <class T>
void put_sample(ByteWriter& w, const core::Sample<T>& s) {
  w.u64(s.sequence);
  w.i64(s.stamp_ns);
  put(w, s.value);
}
template <class T>
bool get_sample(ByteReader& r, core::Sample<T>& s) {
  s.sequence = r.u64();
  s.stamp_ns = r.i64();
  return get(r, s.value);
}

}  // namespace

void put(ByteWriter& w, const msg::GnssFix& m) {
  w.i64(m.stamp_ns);
  put_enum(w, m.source);
  put_enum(w, m.fix_type);
  w.boolean(m.fix_ok);
  w.boolean(m.diff_soln);
  put_enum(w, m.rtk);
  w.f64(m.lat_deg);
  w.f64(m.lon_deg);
  w.f64(m.height_msl_m);
  w.f64(m.h_acc_m);
  w.f64(m.v_acc_m);
  w.f64(m.hdop);
  w.u8(m.satellites);
  w.boolean(m.velocity_valid);
  w.f64(m.vel_north_mps);
  w.f64(m.vel_east_mps);
  w.f64(m.vel_down_mps);
  w.f64(m.ground_speed_mps);
  w.f64(m.course_deg);
  w.i64(m.utc_ns);
  w.u32(m.itow_ms);
}

bool get(ByteReader& r, msg::GnssFix& m) {
  m.stamp_ns = r.i64();
  m.source = get_enum<msg::GnssSource>(r);
  m.fix_type = get_enum<msg::FixType>(r);
  m.fix_ok = r.boolean();
  m.diff_soln = r.boolean();
  m.rtk = get_enum<msg::RtkSolution>(r);
  m.lat_deg = r.f64();
  m.lon_deg = r.f64();
  m.height_msl_m = r.f64();
  m.h_acc_m = r.f64();
  m.v_acc_m = r.f64();
  m.hdop = r.f64();
  m.satellites = r.u8();
  m.velocity_valid = r.boolean();
  m.vel_north_mps = r.f64();
  m.vel_east_mps = r.f64();
  m.vel_down_mps = r.f64();
  m.ground_speed_mps = r.f64();
  m.course_deg = r.f64();
  m.utc_ns = r.i64();
  m.itow_ms = r.u32();
  return !r.underrun();
}

void put(ByteWriter& w, const msg::ImuSample& m) {
  w.i64(m.stamp_ns);
  w.f64(m.roll_deg);
  w.f64(m.pitch_deg);
  w.f64(m.yaw_magnetic_deg);
  w.f64(m.heading_deg);
  for (double v : m.accel_g) w.f64(v);
  for (double v : m.gyro_dps) w.f64(v);
  for (double v : m.mag_ut) w.f64(v);
  w.f64(m.temperature_c);
  w.boolean(m.has_inertial);
  w.u32(m.sequence);
}

bool get(ByteReader& r, msg::ImuSample& m) {
  m.stamp_ns = r.i64();
  m.roll_deg = r.f64();
  m.pitch_deg = r.f64();
  m.yaw_magnetic_deg = r.f64();
  m.heading_deg = r.f64();
  for (double& v : m.accel_g) v = r.f64();
  for (double& v : m.gyro_dps) v = r.f64();
  for (double& v : m.mag_ut) v = r.f64();
  m.temperature_c = r.f64();
  m.has_inertial = r.boolean();
  m.sequence = r.u32();
  return !r.underrun();
}

void put_lidar_header(ByteWriter& w, const msg::LidarScan& m) {
  w.i64(m.stamp_ns);
  w.i64(m.duration_ns);
  w.f32(m.max_range_m);
  w.f32(m.min_range_m);
  w.u32(m.revolution);
  w.u32(m.point_count);
}

bool get_lidar_header(ByteReader& r, msg::LidarScan& m) {
  m.stamp_ns = r.i64();
  m.duration_ns = r.i64();
  m.max_range_m = r.f32();
  m.min_range_m = r.f32();
  m.revolution = r.u32();
  m.point_count = r.u32();
  return !r.underrun() && m.point_count <= msg::LidarScan::kMaxPoints;
}

void put(ByteWriter& w, const msg::LidarScan& m) {
  put_lidar_header(w, m);
  const std::uint32_t n = m.point_count < msg::LidarScan::kMaxPoints
                              ? m.point_count
                              : static_cast<std::uint32_t>(msg::LidarScan::kMaxPoints);
  for (std::uint32_t i = 0; i < n; ++i) {
    const auto& p = m.points[i];
    w.f32(p.bearing_deg);
    w.f32(p.range_m);
    w.u8(p.quality);
    w.i32(p.offset_us);
  }
}

bool get(ByteReader& r, msg::LidarScan& m) {
  if (!get_lidar_header(r, m)) return false;
  for (std::uint32_t i = 0; i < m.point_count; ++i) {
    auto& p = m.points[i];
    p.bearing_deg = r.f32();
    p.range_m = r.f32();
    p.quality = r.u8();
    p.offset_us = r.i32();
  }
  return !r.underrun();
}

void put(ByteWriter& w, const msg::CameraDetections& m) {
  w.i64(m.stamp_ns);
  w.u32(m.frame_index);
  w.u16(m.image_width_px);
  w.u16(m.image_height_px);
  const std::uint32_t n = m.count < msg::CameraDetections::kMaxDetections
                              ? m.count
                              : static_cast<std::uint32_t>(msg::CameraDetections::kMaxDetections);
  w.u32(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    const auto& d = m.detections[i];
    put_enum(w, d.colour);
    put_enum(w, d.shape);
    w.f32(d.bearing_deg);
    w.f32(d.center_x_px);
    w.f32(d.center_y_px);
    w.f32(d.width_px);
    w.f32(d.height_px);
    w.f32(d.area_px);
    w.f32(d.score);
  }
}

bool get(ByteReader& r, msg::CameraDetections& m) {
  m.stamp_ns = r.i64();
  m.frame_index = r.u32();
  m.image_width_px = r.u16();
  m.image_height_px = r.u16();
  m.count = r.u32();
  if (m.count > msg::CameraDetections::kMaxDetections) return false;
  for (std::uint32_t i = 0; i < m.count; ++i) {
    auto& d = m.detections[i];
    d.colour = get_enum<msg::Colour>(r);
    d.shape = get_enum<msg::Shape>(r);
    d.bearing_deg = r.f32();
    d.center_x_px = r.f32();
    d.center_y_px = r.f32();
    d.width_px = r.f32();
    d.height_px = r.f32();
    d.area_px = r.f32();
    d.score = r.f32();
  }
  return !r.underrun();
}

void put(ByteWriter& w, const msg::ArduinoStatus& m) {
  w.i64(m.stamp_ns);
  for (auto v : m.applied_pulse_us) w.u16(v);
  put_enum(w, m.led);
  put_enum(w, m.mode);
  w.boolean(m.estop);
  w.boolean(m.rc_present);
  w.boolean(m.failsafe);
  w.boolean(m.start_switch);
  w.f64(m.supply_v);
  w.u16(m.last_sequence_seen);
}

bool get(ByteReader& r, msg::ArduinoStatus& m) {
  m.stamp_ns = r.i64();
  for (auto& v : m.applied_pulse_us) v = r.u16();
  m.led = get_enum<msg::LedColour>(r);
  m.mode = get_enum<msg::ControlMode>(r);
  m.estop = r.boolean();
  m.rc_present = r.boolean();
  m.failsafe = r.boolean();
  m.start_switch = r.boolean();
  m.supply_v = r.f64();
  m.last_sequence_seen = r.u16();
  return !r.underrun();
}

void put(ByteWriter& w, const msg::OperatorInput& m) {
  w.i64(m.stamp_ns);
  w.u32(m.start_count);
  w.u32(m.hold_count);
  w.boolean(m.hold);
  put_enum(w, m.target_colour);
  put_enum(w, m.target_shape);
}

bool get(ByteReader& r, msg::OperatorInput& m) {
  m.stamp_ns = r.i64();
  m.start_count = r.u32();
  m.hold_count = r.u32();
  m.hold = r.boolean();
  m.target_colour = get_enum<msg::Colour>(r);
  m.target_shape = get_enum<msg::Shape>(r);
  return !r.underrun();
}

void put(ByteWriter& w, const msg::DeviceHealth& m) {
  w.i64(m.stamp_ns);
  put_enum(w, m.device);
  put_enum(w, m.state);
  w.u64(m.bytes_received);
  w.u64(m.frames_ok);
  w.u64(m.checksum_errors);
  w.u64(m.framing_errors);
  w.u64(m.dropped_frames);
  w.u32(m.reopen_count);
  w.i64(m.last_frame_ns);
  w.f64(m.rate_hz);
  w.str16(m.detail_text(), m.detail.size() - 1);
}

bool get(ByteReader& r, msg::DeviceHealth& m) {
  m.stamp_ns = r.i64();
  m.device = get_enum<msg::DeviceId>(r);
  m.state = get_enum<msg::DeviceState>(r);
  m.bytes_received = r.u64();
  m.frames_ok = r.u64();
  m.checksum_errors = r.u64();
  m.framing_errors = r.u64();
  m.dropped_frames = r.u64();
  m.reopen_count = r.u32();
  m.last_frame_ns = r.i64();
  m.rate_hz = r.f64();
  m.set_detail(r.str16());
  return !r.underrun();
}

void put(ByteWriter& w, const msg::ActuatorCommand& m) {
  w.i64(m.stamp_ns);
  for (auto v : m.pulse_us) w.u16(v);
  put_enum(w, m.led);
  w.boolean(m.active);
}

bool get(ByteReader& r, msg::ActuatorCommand& m) {
  m.stamp_ns = r.i64();
  for (auto& v : m.pulse_us) v = r.u16();
  m.led = get_enum<msg::LedColour>(r);
  m.active = r.boolean();
  return !r.underrun();
}

std::size_t encode_raw(std::span<std::uint8_t> out, const RawRecord& raw) {
  ByteWriter w(out);
  w.u8(kLayoutVersion);
  put_enum(w, raw.device);
  put_enum(w, raw.direction);
  w.u8(0);
  w.i64(raw.stamp_ns);
  w.u32(static_cast<std::uint32_t>(raw.bytes.size()));
  w.bytes(raw.bytes);
  return w.overflow() ? 0 : w.size();
}

bool decode_raw(std::span<const std::uint8_t> in, RawRecord& raw) {
  ByteReader r(in);
  if (r.u8() != kLayoutVersion) return false;
  const std::uint8_t device = r.u8();
  const std::uint8_t direction = r.u8();
  r.u8();
  raw.stamp_ns = r.i64();
  const std::uint32_t n = r.u32();
  raw.bytes = r.bytes(n);
  if (r.underrun() || device >= msg::kDeviceCount || direction > 1) return false;
  raw.device = static_cast<msg::DeviceId>(device);
  raw.direction = static_cast<drivers::RawDirection>(direction);
  return true;
}

std::size_t encode_tick(std::span<std::uint8_t> out, std::uint64_t tick_index, core::TimeNs now_ns,
                        const core::Snapshot& snapshot, const msg::ActuatorCommand& command,
                        std::string_view state_path) {
  ByteWriter w(out);
  w.u8(kLayoutVersion);
  w.u64(tick_index);
  w.i64(now_ns);
  put(w, command);
  w.str16(state_path, kMaxStatePathBytes);
  // Lidar: the sample header only; the points travel once in /lidar under the same sequence.
  w.u64(snapshot.lidar.sequence);
  w.i64(snapshot.lidar.stamp_ns);
  put_lidar_header(w, snapshot.lidar.value);
  put_sample(w, snapshot.imu);
  put_sample(w, snapshot.gnss);
  put_sample(w, snapshot.camera);
  put_sample(w, snapshot.arduino);
  put_sample(w, snapshot.operator_input);
  w.u8(static_cast<std::uint8_t>(snapshot.health.size()));
  for (const auto& h : snapshot.health) put_sample(w, h);
  return w.overflow() ? 0 : w.size();
}

bool decode_tick(std::span<const std::uint8_t> in, TickRecordData& out) {
  ByteReader r(in);
  if (r.u8() != kLayoutVersion) return false;
  out.tick_index = r.u64();
  out.now_ns = r.i64();
  if (!get(r, out.command)) return false;
  out.state_path = std::string(r.str16());
  out.snapshot.lidar.sequence = r.u64();
  out.snapshot.lidar.stamp_ns = r.i64();
  if (!get_lidar_header(r, out.snapshot.lidar.value)) return false;
  if (!get_sample(r, out.snapshot.imu) || !get_sample(r, out.snapshot.gnss) ||
      !get_sample(r, out.snapshot.camera) || !get_sample(r, out.snapshot.arduino) ||
      !get_sample(r, out.snapshot.operator_input)) {
    return false;
  }
  if (r.u8() != out.snapshot.health.size()) return false;
  for (auto& h : out.snapshot.health) {
    if (!get_sample(r, h)) return false;
  }
  return !r.underrun() && r.remaining() == 0;
}

std::size_t encode_parameters(std::span<std::uint8_t> out, std::uint64_t tick_index,
                              core::TimeNs stamp_ns, std::span<const NamedValue> values) {
  if (values.size() > 0xFFFF) return 0;
  ByteWriter w(out);
  w.u8(kLayoutVersion);
  w.u64(tick_index);
  w.i64(stamp_ns);
  w.u16(static_cast<std::uint16_t>(values.size()));
  for (const NamedValue& v : values) {
    if (v.name.size() > 0xFF) return 0;
    w.u8(static_cast<std::uint8_t>(v.name.size()));
    w.bytes(std::span(reinterpret_cast<const std::uint8_t*>(v.name.data()), v.name.size()));
    w.f64(v.value);
  }
  return w.overflow() ? 0 : w.size();
}

bool decode_parameters(std::span<const std::uint8_t> in, ParameterSetRecord& out) {
  ByteReader r(in);
  if (r.u8() != kLayoutVersion) return false;
  out.tick_index = r.u64();
  out.stamp_ns = r.i64();
  const std::uint16_t n = r.u16();
  out.values.clear();
  for (std::uint16_t i = 0; i < n && !r.underrun(); ++i) {
    const std::uint8_t length = r.u8();
    const std::span<const std::uint8_t> name = r.bytes(length);
    const double value = r.f64();
    if (r.underrun()) return false;
    out.values.emplace_back(std::string(reinterpret_cast<const char*>(name.data()), name.size()),
                            value);
  }
  return !r.underrun() && r.remaining() == 0;
}

std::string_view layout_schema_name(Layout layout) {
  switch (layout) {
    case Layout::kRaw:
      return "coxswain.RawBytes";
    case Layout::kTick:
      return "coxswain.Tick";
    case Layout::kGnss:
      return "coxswain.GnssFix";
    case Layout::kImu:
      return "coxswain.ImuSample";
    case Layout::kLidar:
      return "coxswain.LidarScan";
    case Layout::kCamera:
      return "coxswain.CameraDetections";
    case Layout::kArduino:
      return "coxswain.ArduinoStatus";
    case Layout::kOperator:
      return "coxswain.OperatorInput";
    case Layout::kHealth:
      return "coxswain.DeviceHealth";
    case Layout::kParameters:
      return "coxswain.ParameterSet";
  }
  return "coxswain.Unknown";
}

// Kept in step with FORMAT.md by layouts_test (each text appears there verbatim).
std::string_view layout_schema_text(Layout layout) {
  switch (layout) {
    case Layout::kRaw:
      return "coxswain.RawBytes v1 (little-endian, packed)\n"
             "u8 version=1; u8 device (0 lidar,1 imu,2 gnss,3 arduino,4 camera); "
             "u8 direction (0 from device,1 to device); u8 reserved=0; i64 stamp_ns (steady); "
             "u32 count; u8[count] bytes\n";
    case Layout::kTick:
      return "coxswain.Tick v1 (little-endian, packed)\n"
             "u8 version=1; u64 tick_index; i64 now_ns; ActuatorCommand command = (i64 stamp_ns; "
             "u16[2] pulse_us; u8 led; u8 active); "
             "u16 n + char[n] state_path; "
             "u64 lidar_sequence + i64 lidar_stamp_ns + LidarHeader; "
             "Sample<ImuSample> imu; Sample<GnssFix> gnss; Sample<CameraDetections> camera; "
             "Sample<ArduinoStatus> arduino; Sample<OperatorInput> operator_input; "
             "u8 n_health + Sample<DeviceHealth>[n_health] (index = device id)\n"
             "Sample<T> = u64 sequence (0 = never written); i64 stamp_ns; the fields of T's "
             "channel "
             "layout after store_sequence\n";
    case Layout::kGnss:
      return "coxswain.GnssFix v1 (little-endian, packed)\n"
             "u8 version=1; u64 store_sequence; i64 stamp_ns; u8 source; u8 fix_type; "
             "u8 fix_ok; u8 diff_soln; u8 rtk; f64 lat_deg; f64 lon_deg; f64 height_msl_m; "
             "f64 h_acc_m; f64 v_acc_m; f64 hdop; u8 satellites; u8 velocity_valid; "
             "f64 vel_north_mps; f64 vel_east_mps; f64 vel_down_mps; f64 ground_speed_mps; "
             "f64 course_deg; i64 utc_ns; u32 itow_ms\n";
    case Layout::kImu:
      return "coxswain.ImuSample v1 (little-endian, packed)\n"
             "u8 version=1; u64 store_sequence; i64 stamp_ns; f64 roll_deg; f64 pitch_deg; "
             "f64 yaw_magnetic_deg; f64 heading_deg; f64[3] accel_g; f64[3] gyro_dps; "
             "f64[3] mag_ut; f64 temperature_c; u8 has_inertial; u32 sequence\n";
    case Layout::kLidar:
      return "coxswain.LidarScan v1 (little-endian, packed)\n"
             "u8 version=1; u64 store_sequence; LidarHeader = i64 stamp_ns; i64 duration_ns; "
             "f32 max_range_m; f32 min_range_m; u32 revolution; u32 point_count; then "
             "point_count x (f32 bearing_deg body frame; f32 range_m (0 = no return); "
             "u8 quality; i32 offset_us)\n";
    case Layout::kCamera:
      return "coxswain.CameraDetections v1 (little-endian, packed)\n"
             "u8 version=1; u64 store_sequence; i64 stamp_ns; u32 frame_index; "
             "u16 image_width_px; u16 image_height_px; u32 count; count x (u8 colour; u8 shape; "
             "f32 bearing_deg; f32 center_x_px; f32 center_y_px; f32 width_px; f32 height_px; "
             "f32 area_px; f32 score)\n";
    case Layout::kArduino:
      return "coxswain.ArduinoStatus v1 (little-endian, packed)\n"
             "u8 version=1; u64 store_sequence; i64 stamp_ns; u16[2] applied_pulse_us; u8 led; "
             "u8 mode; u8 estop; u8 rc_present; u8 failsafe; u8 start_switch; f64 supply_v; "
             "u16 last_sequence_seen\n";
    case Layout::kOperator:
      return "coxswain.OperatorInput v1 (little-endian, packed)\n"
             "u8 version=1; u64 store_sequence; i64 stamp_ns; u32 start_count; u32 hold_count; "
             "u8 hold; u8 target_colour; u8 target_shape\n";
    case Layout::kHealth:
      return "coxswain.DeviceHealth v1 (little-endian, packed)\n"
             "u8 version=1; u64 store_sequence; i64 stamp_ns; u8 device; u8 state; "
             "u64 bytes_received; u64 frames_ok; u64 checksum_errors; u64 framing_errors; "
             "u64 dropped_frames; u32 reopen_count; i64 last_frame_ns; f64 rate_hz; "
             "u16 n + char[n] detail\n";
    case Layout::kParameters:
      return "coxswain.ParameterSet v1 (little-endian, packed)\n"
             "u8 version=1; u64 tick_index (the first tick stepped with the set); i64 stamp_ns; "
             "u16 n; n x (u8 name_length; char[name_length] name; f64 value)\n";
  }
  return "";
}

}  // namespace coxswain::record
