// SPDX-License-Identifier: Apache-2.0
#pragma once
// The recorder's compact binary message layouts (documented field by field in
// src/record/FORMAT.md, and written into each MCAP Schema record as text, both generated from
// the one field list of each message in layouts.cpp). All little-endian, packed, no padding.
// Each channel message starts with its u8 layout version; readers take every version from 1 to
// the current one (a field added later reads as its default from an older message).
//   /raw/<device>       version, device u8, direction u8, reserved u8, stamp_ns i64, count u32,
//                       bytes
//   /gnss /imu /lidar /camera /arduino /operator /health
//                       version, store sequence u64, the message's fields
//   /tick               version, tick index u64, now_ns i64, command, state path, then the
//                       Snapshot sample by sample (lidar as header only: the points are in
//                       /lidar under the same sequence)
//   /params             version, tick index u64, stamp_ns i64, named values (a parameter set
//                       applied between two steps)
// Encoders write into caller buffers and never allocate, so the tick thread can encode.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "coxswain/core/latest_store.hpp"
#include "coxswain/drivers/device_session.hpp"
#include "coxswain/msg/actuator_command.hpp"
#include "coxswain/record/bytes.hpp"

namespace coxswain::record {

/// The layout version each message is written with (see FORMAT.md for what each added).
template <class T>
constexpr std::uint8_t layout_version() {
  if constexpr (std::is_same_v<T, msg::GnssFix>) return 2;  // v2: s_acc_mps
  return 1;
}
inline constexpr std::uint8_t kTickLayoutVersion = 2;  // v2: embeds GnssFix v2
inline constexpr std::uint8_t kRawLayoutVersion = 1;
inline constexpr std::uint8_t kParametersLayoutVersion = 1;
/// The recording's layout generation, in its metadata: the /tick layout's version.
inline constexpr std::uint8_t kLayoutVersion = kTickLayoutVersion;
/// MCAP message encoding of every binary channel.
inline constexpr std::string_view kBinaryMessageEncoding = "coxswain-binary";
/// MCAP schema encoding of the binary channels: the schema data is the layout as text.
inline constexpr std::string_view kLayoutSchemaEncoding = "coxswain-layout";
/// Longest state path kept in a tick record.
inline constexpr std::size_t kMaxStatePathBytes = 255;
/// Upper bound of an encoded tick (checked by a test).
inline constexpr std::size_t kMaxTickBytes = 4096;
/// Upper bound of an encoded /lidar message with LidarScan::kMaxPoints points.
inline constexpr std::size_t kMaxLidarBytes = 64 + msg::LidarScan::kMaxPoints * 13;

// Field writers/readers of each message (no version, no sequence). Writers write the current
// layout version; readers read `version` and return false on a short or malformed buffer.
void put(ByteWriter& w, const msg::GnssFix& m);
void put(ByteWriter& w, const msg::ImuSample& m);
void put(ByteWriter& w, const msg::LidarScan& m);  // header and points
void put(ByteWriter& w, const msg::CameraDetections& m);
void put(ByteWriter& w, const msg::ArduinoStatus& m);
void put(ByteWriter& w, const msg::OperatorInput& m);
void put(ByteWriter& w, const msg::DeviceHealth& m);
void put(ByteWriter& w, const msg::ActuatorCommand& m);
bool get(ByteReader& r, msg::GnssFix& m, std::uint8_t version = layout_version<msg::GnssFix>());
bool get(ByteReader& r, msg::ImuSample& m, std::uint8_t version = layout_version<msg::ImuSample>());
bool get(ByteReader& r, msg::LidarScan& m, std::uint8_t version = layout_version<msg::LidarScan>());
bool get(ByteReader& r, msg::CameraDetections& m,
         std::uint8_t version = layout_version<msg::CameraDetections>());
bool get(ByteReader& r, msg::ArduinoStatus& m,
         std::uint8_t version = layout_version<msg::ArduinoStatus>());
bool get(ByteReader& r, msg::OperatorInput& m,
         std::uint8_t version = layout_version<msg::OperatorInput>());
bool get(ByteReader& r, msg::DeviceHealth& m,
         std::uint8_t version = layout_version<msg::DeviceHealth>());
bool get(ByteReader& r, msg::ActuatorCommand& m,
         std::uint8_t version = layout_version<msg::ActuatorCommand>());
void put_lidar_header(ByteWriter& w, const msg::LidarScan& m);
bool get_lidar_header(ByteReader& r, msg::LidarScan& m);

/// One /raw/<device> message.
struct RawRecord {
  msg::DeviceId device = msg::DeviceId::kLidar;
  drivers::RawDirection direction = drivers::RawDirection::kFromDevice;
  core::TimeNs stamp_ns = 0;
  std::span<const std::uint8_t> bytes;  // view into the decoded buffer
};
/// Bytes written, 0 when `out` is too small.
std::size_t encode_raw(std::span<std::uint8_t> out, const RawRecord& raw);
bool decode_raw(std::span<const std::uint8_t> in, RawRecord& raw);

/// A decoded-message channel message: version, store sequence, fields.
template <class T>
std::size_t encode_sample(std::span<std::uint8_t> out, std::uint64_t sequence, const T& m) {
  ByteWriter w(out);
  w.u8(layout_version<T>());
  w.u64(sequence);
  put(w, m);
  return w.overflow() ? 0 : w.size();
}
template <class T>
bool decode_sample(std::span<const std::uint8_t> in, std::uint64_t& sequence, T& m) {
  ByteReader r(in);
  const std::uint8_t version = r.u8();
  if (version < 1 || version > layout_version<T>()) return false;
  sequence = r.u64();
  return get(r, m, version) && !r.underrun();
}

/// One /tick message decoded. `snapshot.lidar.value` holds the scan header only (no points).
struct TickRecordData {
  std::uint64_t tick_index = 0;
  core::TimeNs now_ns = 0;
  msg::ActuatorCommand command;
  std::string state_path;
  core::Snapshot snapshot;
};
/// Encodes a tick into `out` (kMaxTickBytes is always enough). Bytes written, 0 on overflow.
/// No allocation.
std::size_t encode_tick(std::span<std::uint8_t> out, std::uint64_t tick_index, core::TimeNs now_ns,
                        const core::Snapshot& snapshot, const msg::ActuatorCommand& command,
                        std::string_view state_path);
bool decode_tick(std::span<const std::uint8_t> in, TickRecordData& out);

/// Upper bound of an encoded /params message.
inline constexpr std::size_t kMaxParameterBytes = 16384;
/// One value of a parameter set, by name (e.g. "heading_pid.kp_per_deg").
struct NamedValue {
  std::string_view name;  // at most 255 bytes
  double value = 0.0;
};
/// One /params message decoded.
struct ParameterSetRecord {
  std::uint64_t tick_index = 0;  // the first tick stepped with the set
  core::TimeNs stamp_ns = 0;
  std::vector<std::pair<std::string, double>> values;
};
/// Encodes a parameter set into `out`. Bytes written, 0 on overflow (or a name over 255 bytes).
/// No allocation.
std::size_t encode_parameters(std::span<std::uint8_t> out, std::uint64_t tick_index,
                              core::TimeNs stamp_ns, std::span<const NamedValue> values);
bool decode_parameters(std::span<const std::uint8_t> in, ParameterSetRecord& out);

/// The binary layouts a recording uses; each has a schema name and a text description.
enum class Layout : std::uint8_t {
  kRaw,
  kTick,
  kGnss,
  kImu,
  kLidar,
  kCamera,
  kArduino,
  kOperator,
  kHealth,
  kParameters,
};
inline constexpr std::size_t kLayoutCount = static_cast<std::size_t>(Layout::kParameters) + 1;
[[nodiscard]] std::string_view layout_schema_name(Layout layout);
/// The layout as text (also in FORMAT.md): the schema data of its MCAP Schema record.
[[nodiscard]] std::string_view layout_schema_text(Layout layout);

}  // namespace coxswain::record
