// SPDX-License-Identifier: Apache-2.0
#include "coxswain/record/layouts.hpp"

#include <array>
#include <concepts>
#include <memory>
#include <string>
#include <type_traits>

#include "message_fields.hpp"

namespace coxswain::record {
namespace {

using detail::fields;
using detail::IsStdArray;
using detail::lidar_header_fields;
using detail::ListInfo;

// Each message's fields are listed once, in its `fields(io, m, version)` below. The same list
// writes (WriteIo), reads (ReadIo) and documents (DescribeIo: the schema text in every recording
// and in FORMAT.md) the layout, so the three cannot drift apart. A field added to a message later
// is listed with `io.since(version, ...)`: older messages read it as the struct's default.

template <class T>
void write_value(ByteWriter& w, const T& v) {
  if constexpr (IsStdArray<T>::value) {
    for (const auto& e : v) write_value(w, e);
  } else if constexpr (std::is_same_v<T, bool>) {
    w.boolean(v);
  } else if constexpr (std::is_enum_v<T>) {
    static_assert(sizeof(T) == 1, "enums travel as u8");
    w.u8(static_cast<std::uint8_t>(v));
  } else if constexpr (std::is_same_v<T, float>) {
    w.f32(v);
  } else if constexpr (std::is_same_v<T, double>) {
    w.f64(v);
  } else if constexpr (std::is_same_v<T, std::uint8_t>) {
    w.u8(v);
  } else if constexpr (std::is_same_v<T, std::uint16_t>) {
    w.u16(v);
  } else if constexpr (std::is_same_v<T, std::uint32_t>) {
    w.u32(v);
  } else if constexpr (std::is_same_v<T, std::uint64_t>) {
    w.u64(v);
  } else if constexpr (std::is_same_v<T, std::int32_t>) {
    w.i32(v);
  } else {
    static_assert(std::is_same_v<T, std::int64_t>, "no wire type for this field");
    w.i64(v);
  }
}

template <class T>
void read_value(ByteReader& r, T& v) {
  if constexpr (IsStdArray<T>::value) {
    for (auto& e : v) read_value(r, e);
  } else if constexpr (std::is_same_v<T, bool>) {
    v = r.boolean();
  } else if constexpr (std::is_enum_v<T>) {
    v = static_cast<T>(r.u8());
  } else if constexpr (std::is_same_v<T, float>) {
    v = r.f32();
  } else if constexpr (std::is_same_v<T, double>) {
    v = r.f64();
  } else if constexpr (std::is_same_v<T, std::uint8_t>) {
    v = r.u8();
  } else if constexpr (std::is_same_v<T, std::uint16_t>) {
    v = r.u16();
  } else if constexpr (std::is_same_v<T, std::uint32_t>) {
    v = r.u32();
  } else if constexpr (std::is_same_v<T, std::uint64_t>) {
    v = r.u64();
  } else if constexpr (std::is_same_v<T, std::int32_t>) {
    v = r.i32();
  } else {
    static_assert(std::is_same_v<T, std::int64_t>, "no wire type for this field");
    v = r.i64();
  }
}

template <class T>
void describe_type(std::string& out) {
  if constexpr (IsStdArray<T>::value) {
    describe_type<typename T::value_type>(out);
    out += '[' + std::to_string(std::tuple_size_v<T>) + ']';
  } else if constexpr (std::is_same_v<T, bool> || std::is_enum_v<T> ||
                       std::is_same_v<T, std::uint8_t>) {
    out += "u8";
  } else if constexpr (std::is_same_v<T, float>) {
    out += "f32";
  } else if constexpr (std::is_same_v<T, double>) {
    out += "f64";
  } else if constexpr (std::is_same_v<T, std::uint16_t>) {
    out += "u16";
  } else if constexpr (std::is_same_v<T, std::uint32_t>) {
    out += "u32";
  } else if constexpr (std::is_same_v<T, std::uint64_t>) {
    out += "u64";
  } else if constexpr (std::is_same_v<T, std::int32_t>) {
    out += "i32";
  } else {
    out += "i64";
  }
}

struct WriteIo {
  static constexpr bool kReads = false;
  ByteWriter& w;
  std::uint8_t version = 0;

  template <class T>
  void field(std::string_view /*name*/, const T& v, std::string_view /*note*/ = {}) {
    write_value(w, v);
  }
  template <class T>
  void since(std::uint8_t first_version, std::string_view name, const T& v) {
    if (version >= first_version) field(name, v);
  }
  // `count` elements of `items` (at most `max_count`), written by `element(io, item)`; the count
  // itself is a field listed before (`count_written`) or written here (`count_name`).
  template <class Items, class Element>
  void elements(const ListInfo& list, std::uint32_t count, std::size_t max_count,
                const Items& items, Element element) {
    const std::uint32_t n = count < max_count ? count : static_cast<std::uint32_t>(max_count);
    if (!list.count_written) w.u32(n);
    for (std::uint32_t i = 0; i < n; ++i) element(*this, items[i]);
  }
  // The packed layout stores columns row by row, like elements.
  template <class Items, class Element>
  void columns(const ListInfo& list, std::uint32_t count, std::size_t max_count, const Items& items,
               Element element) {
    elements(list, count, max_count, items, element);
  }
  void text(std::string_view /*name*/, std::string_view value, std::size_t max_len) {
    w.str16(value, max_len);
  }
};

struct ReadIo {
  static constexpr bool kReads = true;
  ByteReader& r;
  std::uint8_t version = 0;
  bool ok = true;

  template <class T>
  void field(std::string_view /*name*/, T& v, std::string_view /*note*/ = {}) {
    read_value(r, v);
  }
  template <class T>
  void since(std::uint8_t first_version, std::string_view name, T& v) {
    if (version >= first_version) field(name, v);
  }
  template <class Items, class Element>
  void elements(const ListInfo& list, std::uint32_t& count, std::size_t max_count, Items& items,
                Element element) {
    if (!list.count_written) count = r.u32();
    if (r.underrun() || count > max_count) {
      ok = false;
      return;
    }
    for (std::uint32_t i = 0; i < count; ++i) element(*this, items[i]);
  }
  template <class Items, class Element>
  void columns(const ListInfo& list, std::uint32_t& count, std::size_t max_count, Items& items,
               Element element) {
    elements(list, count, max_count, items, element);
  }
  template <class Setter>
  void text(std::string_view /*name*/, Setter set) {
    set(r.str16());
  }
};

struct DescribeIo {
  static constexpr bool kReads = false;
  std::string out;
  std::uint8_t version = 0;

  void separate() {
    if (!out.empty() && out.back() != '(') out += "; ";
  }
  template <class T>
  void field(std::string_view name, const T& /*v*/, std::string_view note = {}) {
    separate();
    describe_type<T>(out);
    out += ' ';
    out += name;
    if (!note.empty()) {
      out += " (";
      out += note;
      out += ')';
    }
  }
  template <class T>
  void since(std::uint8_t first_version, std::string_view name, const T& v) {
    field(name, v, "since v" + std::to_string(first_version));
  }
  template <class Items, class Element>
  void elements(const ListInfo& list, std::uint32_t /*count*/, std::size_t /*max_count*/,
                const Items& items, Element element) {
    if (!list.count_written) {
      separate();
      out += "u32 ";
      out += list.count;
    }
    separate();
    out += list.count;
    out += " x (";
    element(*this, items[0]);
    out += ')';
  }
  template <class Items, class Element>
  void columns(const ListInfo& list, std::uint32_t count, std::size_t max_count, const Items& items,
               Element element) {
    elements(list, count, max_count, items, element);
  }
  void text(std::string_view name, std::string_view /*value*/, std::size_t /*max_len*/) {
    separate();
    out += "u16 n + char[n] ";
    out += name;
  }
};

template <class M>
void write_fields(ByteWriter& w, const M& m, std::uint8_t version) {
  WriteIo io{w, version};
  fields(io, m);
}

template <class M>
bool read_fields(ByteReader& r, M& m, std::uint8_t version) {
  ReadIo io{r, version};
  fields(io, m);
  return io.ok && !r.underrun();
}

template <class M>
std::string describe_fields(std::uint8_t version) {
  DescribeIo io{{}, version};
  const auto m = std::make_unique<const M>();  // a scan is 64 KiB: not on the stack
  fields(io, *m);
  return io.out;
}

// The version of each message embedded in a /tick message of version `tick_version`.
template <class T>
std::uint8_t embedded_version(std::uint8_t tick_version) {
  if constexpr (std::is_same_v<T, msg::GnssFix>) return tick_version >= 2 ? 2 : 1;
  return 1;
}

template <class T>
void put_sample(ByteWriter& w, const core::Sample<T>& s) {
  w.u64(s.sequence);
  w.i64(s.stamp_ns);
  write_fields(w, s.value, layout_version<T>());
}
template <class T>
bool get_sample(ByteReader& r, core::Sample<T>& s, std::uint8_t tick_version) {
  s.sequence = r.u64();
  s.stamp_ns = r.i64();
  return read_fields(r, s.value, embedded_version<T>(tick_version));
}

bool known_version(std::uint8_t version, std::uint8_t current) {
  return version >= 1 && version <= current;
}

}  // namespace

void put(ByteWriter& w, const msg::GnssFix& m) {
  write_fields(w, m, layout_version<msg::GnssFix>());
}
bool get(ByteReader& r, msg::GnssFix& m, std::uint8_t version) {
  return read_fields(r, m, version);
}
void put(ByteWriter& w, const msg::ImuSample& m) {
  write_fields(w, m, layout_version<msg::ImuSample>());
}
bool get(ByteReader& r, msg::ImuSample& m, std::uint8_t version) {
  return read_fields(r, m, version);
}
void put(ByteWriter& w, const msg::LidarScan& m) {
  write_fields(w, m, layout_version<msg::LidarScan>());
}
bool get(ByteReader& r, msg::LidarScan& m, std::uint8_t version) {
  return read_fields(r, m, version);
}
void put(ByteWriter& w, const msg::CameraDetections& m) {
  write_fields(w, m, layout_version<msg::CameraDetections>());
}
bool get(ByteReader& r, msg::CameraDetections& m, std::uint8_t version) {
  return read_fields(r, m, version);
}
void put(ByteWriter& w, const msg::ArduinoStatus& m) {
  write_fields(w, m, layout_version<msg::ArduinoStatus>());
}
bool get(ByteReader& r, msg::ArduinoStatus& m, std::uint8_t version) {
  return read_fields(r, m, version);
}
void put(ByteWriter& w, const msg::OperatorInput& m) {
  write_fields(w, m, layout_version<msg::OperatorInput>());
}
bool get(ByteReader& r, msg::OperatorInput& m, std::uint8_t version) {
  return read_fields(r, m, version);
}
void put(ByteWriter& w, const msg::DeviceHealth& m) {
  write_fields(w, m, layout_version<msg::DeviceHealth>());
}
bool get(ByteReader& r, msg::DeviceHealth& m, std::uint8_t version) {
  return read_fields(r, m, version);
}
void put(ByteWriter& w, const msg::ActuatorCommand& m) {
  write_fields(w, m, layout_version<msg::ActuatorCommand>());
}
bool get(ByteReader& r, msg::ActuatorCommand& m, std::uint8_t version) {
  return read_fields(r, m, version);
}

void put_lidar_header(ByteWriter& w, const msg::LidarScan& m) {
  WriteIo io{w, layout_version<msg::LidarScan>()};
  lidar_header_fields(io, m);
}

bool get_lidar_header(ByteReader& r, msg::LidarScan& m) {
  ReadIo io{r, layout_version<msg::LidarScan>()};
  lidar_header_fields(io, m);
  return !r.underrun() && m.point_count <= msg::LidarScan::kMaxPoints;
}

std::size_t encode_raw(std::span<std::uint8_t> out, const RawRecord& raw) {
  ByteWriter w(out);
  w.u8(kRawLayoutVersion);
  write_value(w, raw.device);
  write_value(w, raw.direction);
  w.u8(0);
  w.i64(raw.stamp_ns);
  w.u32(static_cast<std::uint32_t>(raw.bytes.size()));
  w.bytes(raw.bytes);
  return w.overflow() ? 0 : w.size();
}

bool decode_raw(std::span<const std::uint8_t> in, RawRecord& raw) {
  ByteReader r(in);
  if (!known_version(r.u8(), kRawLayoutVersion)) return false;
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
  w.u8(kTickLayoutVersion);
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
  const std::uint8_t version = r.u8();
  if (!known_version(version, kTickLayoutVersion)) return false;
  out.tick_index = r.u64();
  out.now_ns = r.i64();
  if (!get(r, out.command, embedded_version<msg::ActuatorCommand>(version))) return false;
  out.state_path = std::string(r.str16());
  out.snapshot.lidar.sequence = r.u64();
  out.snapshot.lidar.stamp_ns = r.i64();
  if (!get_lidar_header(r, out.snapshot.lidar.value)) return false;
  if (!get_sample(r, out.snapshot.imu, version) || !get_sample(r, out.snapshot.gnss, version) ||
      !get_sample(r, out.snapshot.camera, version) ||
      !get_sample(r, out.snapshot.arduino, version) ||
      !get_sample(r, out.snapshot.operator_input, version)) {
    return false;
  }
  if (r.u8() != out.snapshot.health.size()) return false;
  for (auto& h : out.snapshot.health) {
    if (!get_sample(r, h, version)) return false;
  }
  return !r.underrun() && r.remaining() == 0;
}

std::size_t encode_parameters(std::span<std::uint8_t> out, std::uint64_t tick_index,
                              core::TimeNs stamp_ns, std::span<const NamedValue> values) {
  if (values.size() > 0xFFFF) return 0;
  ByteWriter w(out);
  w.u8(kParametersLayoutVersion);
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
  if (!known_version(r.u8(), kParametersLayoutVersion)) return false;
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

namespace {

template <class T>
std::string sample_text(std::string_view name) {
  const std::uint8_t v = layout_version<T>();
  return "coxswain." + std::string(name) + " v" + std::to_string(v) +
         " (little-endian, packed)\nu8 version=" + std::to_string(v) + "; u64 store_sequence; " +
         describe_fields<T>(v) + "\n";
}

std::string lidar_text() {
  const std::uint8_t v = layout_version<msg::LidarScan>();
  DescribeIo header{{}, v};
  const auto scan = std::make_unique<msg::LidarScan>();
  lidar_header_fields(header, *scan);
  std::string all = describe_fields<msg::LidarScan>(v);
  return "coxswain.LidarScan v" + std::to_string(v) +
         " (little-endian, packed)\nu8 version=" + std::to_string(v) +
         "; u64 store_sequence; LidarHeader = (" + header.out + "); then " +
         all.substr(header.out.size() + 2) + "\n";
}

std::string tick_text() {
  const std::string v = std::to_string(kTickLayoutVersion);
  return "coxswain.Tick v" + v + " (little-endian, packed)\nu8 version=" + v +
         "; u64 tick_index; i64 now_ns; ActuatorCommand command = (" +
         describe_fields<msg::ActuatorCommand>(1) +
         "); u16 n + char[n] state_path; u64 lidar_sequence + i64 lidar_stamp_ns + LidarHeader; "
         "Sample<ImuSample> imu; Sample<GnssFix> gnss; Sample<CameraDetections> camera; "
         "Sample<ArduinoStatus> arduino; Sample<OperatorInput> operator_input; "
         "u8 n_health + Sample<DeviceHealth>[n_health] (index = device id)\n"
         "Sample<T> = u64 sequence (0 = never written); i64 stamp_ns; the fields of T's channel "
         "layout after store_sequence (a tick of version 1 embeds GnssFix v1)\n";
}

std::string build_schema_text(Layout layout) {
  switch (layout) {
    case Layout::kRaw:
      return "coxswain.RawBytes v1 (little-endian, packed)\n"
             "u8 version=1; u8 device (0 lidar,1 imu,2 gnss,3 arduino,4 camera); "
             "u8 direction (0 from device,1 to device); u8 reserved=0; i64 stamp_ns (steady); "
             "u32 count; u8[count] bytes\n";
    case Layout::kTick:
      return tick_text();
    case Layout::kGnss:
      return sample_text<msg::GnssFix>("GnssFix");
    case Layout::kImu:
      return sample_text<msg::ImuSample>("ImuSample");
    case Layout::kLidar:
      return lidar_text();
    case Layout::kCamera:
      return sample_text<msg::CameraDetections>("CameraDetections");
    case Layout::kArduino:
      return sample_text<msg::ArduinoStatus>("ArduinoStatus");
    case Layout::kOperator:
      return sample_text<msg::OperatorInput>("OperatorInput");
    case Layout::kHealth:
      return sample_text<msg::DeviceHealth>("DeviceHealth");
    case Layout::kParameters:
      return "coxswain.ParameterSet v1 (little-endian, packed)\n"
             "u8 version=1; u64 tick_index (the first tick stepped with the set); i64 stamp_ns; "
             "u16 n; n x (u8 name_length; char[name_length] name; f64 value)\n";
  }
  return "";
}

}  // namespace

// Built once from the field lists; kept in step with FORMAT.md by layouts_test (each text
// appears there verbatim).
std::string_view layout_schema_text(Layout layout) {
  static const std::array<std::string, kLayoutCount> texts = [] {
    std::array<std::string, kLayoutCount> t;
    for (std::size_t i = 0; i < kLayoutCount; ++i) {
      t[i] = build_schema_text(static_cast<Layout>(i));
    }
    return t;
  }();
  const auto i = static_cast<std::size_t>(layout);
  return i < texts.size() ? std::string_view(texts[i]) : std::string_view();
}

}  // namespace coxswain::record
