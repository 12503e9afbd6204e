// SPDX-License-Identifier: Apache-2.0
#include "coxswain/record/proto_codec.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "message_fields.hpp"

namespace coxswain::record {
namespace {

using detail::fields;
using detail::IsStdArray;
using detail::lidar_header_fields;
using detail::ListInfo;

// ---- wire format ------------------------------------------------------------------------------

enum Wire : std::uint8_t { kVarint = 0, kFixed64 = 1, kLen = 2, kFixed32 = 5 };

// Writes into `out`; past its end it only counts, so encoding into an empty span sizes a message
// (a nested message's length precedes it on the wire).
class Sink {
 public:
  explicit Sink(std::span<std::uint8_t> out) : out_(out) {}
  void byte(std::uint8_t b) {
    if (n_ < out_.size()) out_[n_] = b;
    ++n_;
  }
  void varint(std::uint64_t v) {
    while (v >= 0x80) {
      byte(static_cast<std::uint8_t>(v | 0x80));
      v >>= 7;
    }
    byte(static_cast<std::uint8_t>(v));
  }
  void fixed32(std::uint32_t v) {
    for (int i = 0; i < 4; ++i) byte(static_cast<std::uint8_t>(v >> (8 * i)));
  }
  void fixed64(std::uint64_t v) {
    for (int i = 0; i < 8; ++i) byte(static_cast<std::uint8_t>(v >> (8 * i)));
  }
  void bytes(std::span<const std::uint8_t> b) {
    // An empty span may hold a null pointer, which memcpy must not be given.
    if (!b.empty() && n_ < out_.size()) {
      std::memcpy(out_.data() + n_, b.data(), std::min(b.size(), out_.size() - n_));
    }
    n_ += b.size();
  }
  void tag(std::uint32_t number, Wire wire) {
    varint((static_cast<std::uint64_t>(number) << 3) | wire);
  }
  [[nodiscard]] std::size_t size() const { return n_; }
  [[nodiscard]] bool overflow() const { return n_ > out_.size(); }

 private:
  std::span<std::uint8_t> out_;
  std::size_t n_ = 0;
};

std::size_t finish(const Sink& s) { return s.overflow() ? 0 : s.size(); }

// Reads one value at a time; any read past the end or a malformed varint clears `ok`.
struct Cursor {
  std::span<const std::uint8_t> in;
  std::size_t pos = 0;
  bool ok = true;

  [[nodiscard]] bool at_end() const { return pos >= in.size(); }
  std::uint64_t varint() {
    std::uint64_t v = 0;
    for (int shift = 0; shift < 64; shift += 7) {
      if (pos >= in.size()) break;
      const std::uint8_t b = in[pos++];
      v |= static_cast<std::uint64_t>(b & 0x7F) << shift;
      if ((b & 0x80) == 0) return v;
    }
    ok = false;
    return 0;
  }
  std::uint64_t fixed(std::size_t bytes) {
    if (pos > in.size() || in.size() - pos < bytes) {
      ok = false;
      pos = in.size();
      return 0;
    }
    std::uint64_t v = 0;
    for (std::size_t i = 0; i < bytes; ++i) {
      v |= static_cast<std::uint64_t>(in[pos + i]) << (8 * i);
    }
    pos += bytes;
    return v;
  }
  std::span<const std::uint8_t> take(std::uint64_t n) {
    if (n > in.size() - pos) {
      ok = false;
      pos = in.size();
      return {};
    }
    const auto s = in.subspan(pos, static_cast<std::size_t>(n));
    pos += static_cast<std::size_t>(n);
    return s;
  }
};

// One occurrence of a field: its wire type and its value (a varint or fixed value, or the payload
// of a length-delimited field).
struct FieldRef {
  std::uint8_t wire = 0;
  std::uint64_t value = 0;
  std::span<const std::uint8_t> payload;
};

// Calls `fn(FieldRef)` for every occurrence of `number` in `message`, in order. False when the
// message is malformed (checked to its end whatever the number).
template <class Fn>
bool for_each_occurrence(std::span<const std::uint8_t> message, std::uint32_t number, Fn fn) {
  Cursor c{message};
  while (c.ok && !c.at_end()) {
    const std::uint64_t key = c.varint();
    const auto wire = static_cast<std::uint8_t>(key & 7);
    FieldRef f{wire, 0, {}};
    switch (wire) {
      case kVarint:
        f.value = c.varint();
        break;
      case kFixed64:
        f.value = c.fixed(8);
        break;
      case kFixed32:
        f.value = c.fixed(4);
        break;
      case kLen:
        f.payload = c.take(c.varint());
        break;
      default:
        return false;  // groups and unknown wire types: never written by us
    }
    if (!c.ok || (key >> 3) == 0) return false;
    if ((key >> 3) == number) fn(f);
  }
  return c.ok;
}

// The last occurrence wins (protobuf's rule for a scalar).
bool find_last(std::span<const std::uint8_t> message, std::uint32_t number, bool& present,
               FieldRef& out) {
  present = false;
  return for_each_occurrence(message, number, [&](const FieldRef& f) {
    present = true;
    out = f;
  });
}

// ---- scalars ----------------------------------------------------------------------------------

// google.protobuf.FieldDescriptorProto.Type values.
enum ProtoType : std::uint8_t {
  kTypeDouble = 1,
  kTypeFloat = 2,
  kTypeUint64 = 4,
  kTypeBool = 8,
  kTypeString = 9,
  kTypeMessage = 11,
  kTypeBytes = 12,
  kTypeUint32 = 13,
  kTypeSint32 = 17,
  kTypeSint64 = 18,
};

// How each C++ field type travels: unsigned integers and enums as varints, signed integers
// zig-zagged (small negatives stay short), floating point as fixed 32/64 bits.
template <class T>
constexpr ProtoType proto_type() {
  if constexpr (std::is_same_v<T, bool>) {
    return kTypeBool;
  } else if constexpr (std::is_enum_v<T> || std::is_same_v<T, std::uint8_t> ||
                       std::is_same_v<T, std::uint16_t> || std::is_same_v<T, std::uint32_t>) {
    return kTypeUint32;
  } else if constexpr (std::is_same_v<T, std::uint64_t>) {
    return kTypeUint64;
  } else if constexpr (std::is_same_v<T, std::int32_t>) {
    return kTypeSint32;
  } else if constexpr (std::is_same_v<T, std::int64_t>) {
    return kTypeSint64;
  } else if constexpr (std::is_same_v<T, float>) {
    return kTypeFloat;
  } else {
    static_assert(std::is_same_v<T, double>, "no protobuf type for this field");
    return kTypeDouble;
  }
}

template <class T>
constexpr Wire wire_of() {
  constexpr ProtoType t = proto_type<T>();
  if constexpr (t == kTypeFloat) return kFixed32;
  if constexpr (t == kTypeDouble) return kFixed64;
  return kVarint;
}

std::string_view proto_type_name(std::uint8_t type) {
  switch (type) {
    case kTypeDouble:
      return "double";
    case kTypeFloat:
      return "float";
    case kTypeUint64:
      return "uint64";
    case kTypeBool:
      return "bool";
    case kTypeString:
      return "string";
    case kTypeBytes:
      return "bytes";
    case kTypeUint32:
      return "uint32";
    case kTypeSint32:
      return "sint32";
    case kTypeSint64:
      return "sint64";
    default:
      return "?";
  }
}

std::uint64_t zigzag(std::int64_t v) {
  return (static_cast<std::uint64_t>(v) << 1) ^ static_cast<std::uint64_t>(v >> 63);
}
std::int64_t unzigzag(std::uint64_t v) {
  return static_cast<std::int64_t>(v >> 1) ^ -static_cast<std::int64_t>(v & 1);
}

// The value alone (no tag).
template <class T>
void put_value(Sink& s, const T& v) {
  constexpr ProtoType t = proto_type<T>();
  if constexpr (t == kTypeFloat) {
    s.fixed32(std::bit_cast<std::uint32_t>(v));
  } else if constexpr (t == kTypeDouble) {
    s.fixed64(std::bit_cast<std::uint64_t>(v));
  } else if constexpr (t == kTypeSint32 || t == kTypeSint64) {
    s.varint(zigzag(static_cast<std::int64_t>(v)));
  } else if constexpr (std::is_same_v<T, bool>) {
    s.varint(v ? 1U : 0U);
  } else {
    s.varint(static_cast<std::uint64_t>(v));
  }
}

// A raw value (as read for wire type `wire_of<T>()`) into `v`; false when out of range.
template <class T>
bool set_value(std::uint64_t raw, T& v) {
  constexpr ProtoType t = proto_type<T>();
  if constexpr (t == kTypeFloat) {
    v = std::bit_cast<float>(static_cast<std::uint32_t>(raw));
  } else if constexpr (t == kTypeDouble) {
    v = std::bit_cast<double>(raw);
  } else if constexpr (t == kTypeSint32) {
    const std::int64_t x = unzigzag(raw);
    if (x < INT32_MIN || x > INT32_MAX) return false;
    v = static_cast<std::int32_t>(x);
  } else if constexpr (t == kTypeSint64) {
    v = unzigzag(raw);
  } else if constexpr (std::is_same_v<T, bool>) {
    v = raw != 0;
  } else if constexpr (std::is_enum_v<T>) {
    if (raw > 0xFF) return false;
    v = static_cast<T>(raw);
  } else {
    if (raw > static_cast<std::uint64_t>(std::numeric_limits<T>::max())) return false;
    v = static_cast<T>(raw);
  }
  return true;
}

template <class T>
std::uint64_t read_value(Cursor& c) {
  constexpr Wire w = wire_of<T>();
  if constexpr (w == kFixed32) return c.fixed(4);
  if constexpr (w == kFixed64) return c.fixed(8);
  return c.varint();
}

// ---- one field, written and read --------------------------------------------------------------

template <class T>
void put_field(Sink& s, std::uint32_t number, const T& v) {
  if constexpr (IsStdArray<T>::value) {
    // Packed repeated: one length-delimited run of values.
    using E = typename T::value_type;
    Sink sizer({});
    for (const E& e : v) put_value(sizer, e);
    s.tag(number, kLen);
    s.varint(sizer.size());
    for (const E& e : v) put_value(s, e);
  } else {
    s.tag(number, wire_of<T>());
    put_value(s, v);
  }
}

// Leaves `v` as it is when the field is absent (the caller starts from a default message).
template <class T>
bool get_field(std::span<const std::uint8_t> message, std::uint32_t number, T& v) {
  bool present = false;
  FieldRef f;
  if (!find_last(message, number, present, f)) return false;
  if (!present) return true;
  if constexpr (IsStdArray<T>::value) {
    using E = typename T::value_type;
    if (f.wire != kLen) return false;
    Cursor c{f.payload};
    for (E& e : v) {
      const std::uint64_t raw = read_value<E>(c);
      if (!c.ok || !set_value(raw, e)) return false;
    }
    return c.at_end();
  } else {
    if (f.wire != wire_of<T>()) return false;
    return set_value(f.value, v);
  }
}

// Visits the members of one record of a column list: `fn(index, name, value)` for each.
template <class Fn>
struct MemberIo {
  static constexpr bool kReads = false;
  Fn fn;
  std::size_t index = 0;
  template <class T>
  void field(std::string_view name, T& v, std::string_view /*note*/ = {}) {
    static_assert(!IsStdArray<std::remove_const_t<T>>::value, "no arrays inside columns");
    fn(index++, name, v);
  }
};
template <class Fn>
MemberIo(Fn) -> MemberIo<Fn>;

template <class Item, class Element>
std::size_t member_count(const Item& item, Element element) {
  MemberIo io{[](std::size_t, std::string_view, const auto&) {}};
  element(io, item);
  return io.index;
}

// ---- writing ----------------------------------------------------------------------------------

struct ProtoWriteIo {
  static constexpr bool kReads = false;
  Sink& s;
  std::uint32_t next = 1;

  template <class T>
  void field(std::string_view /*name*/, const T& v, std::string_view /*note*/ = {}) {
    put_field(s, next++, v);
  }
  template <class T>
  void since(std::uint8_t /*first_version*/, std::string_view name, const T& v) {
    field(name, v);
  }
  template <class Items, class Element>
  void elements(const ListInfo& /*list*/, std::uint32_t count, std::size_t max_count,
                const Items& items, Element element) {
    const std::uint32_t number = next++;
    const std::size_t n = std::min<std::size_t>(count, max_count);
    for (std::size_t i = 0; i < n; ++i) {
      Sink sizer({});
      ProtoWriteIo size_io{sizer};
      element(size_io, items[i]);
      s.tag(number, kLen);
      s.varint(sizer.size());
      ProtoWriteIo io{s};
      element(io, items[i]);
    }
  }
  template <class Items, class Element>
  void columns(const ListInfo& /*list*/, std::uint32_t count, std::size_t max_count,
               const Items& items, Element element) {
    const std::size_t n = std::min<std::size_t>(count, max_count);
    const std::size_t members = member_count(items[0], element);
    for (std::size_t k = 0; k < members; ++k) {
      const std::uint32_t number = next++;
      if (n == 0) continue;  // an empty packed field is left out
      auto put_column = [&](Sink& out) {
        for (std::size_t i = 0; i < n; ++i) {
          MemberIo io{[&](std::size_t index, std::string_view, const auto& v) {
            if (index == k) put_value(out, v);
          }};
          element(io, items[i]);
        }
      };
      Sink sizer({});
      put_column(sizer);
      s.tag(number, kLen);
      s.varint(sizer.size());
      put_column(s);
    }
  }
  void text(std::string_view /*name*/, std::string_view value, std::size_t max_len) {
    const std::string_view cut = value.substr(0, max_len);
    s.tag(next++, kLen);
    s.varint(cut.size());
    s.bytes(std::span(reinterpret_cast<const std::uint8_t*>(cut.data()), cut.size()));
  }
};

// A nested message: its fields numbered from 1.
template <class M>
void put_message(Sink& s, std::uint32_t number, const M& m) {
  auto body = [&](Sink& out) {
    ProtoWriteIo io{out, 1};
    fields(io, m);
  };
  Sink sizer({});
  body(sizer);
  s.tag(number, kLen);
  s.varint(sizer.size());
  body(s);
}

// ---- reading ----------------------------------------------------------------------------------

struct ProtoReadIo {
  static constexpr bool kReads = true;
  std::span<const std::uint8_t> message;
  std::uint32_t next = 1;
  bool ok = true;

  template <class T>
  void field(std::string_view /*name*/, T& v, std::string_view /*note*/ = {}) {
    if (!get_field(message, next++, v)) ok = false;
  }
  template <class T>
  void since(std::uint8_t /*first_version*/, std::string_view name, T& v) {
    field(name, v);
  }
  template <class Items, class Element>
  void elements(const ListInfo& list, std::uint32_t& count, std::size_t max_count, Items& items,
                Element element) {
    const std::uint32_t number = next++;
    std::uint32_t n = 0;
    const bool well_formed = for_each_occurrence(message, number, [&](const FieldRef& f) {
      if (f.wire != kLen || n >= max_count) {
        ok = false;
        return;
      }
      ProtoReadIo io{f.payload};
      element(io, items[n]);
      if (!io.ok) ok = false;
      ++n;
    });
    if (!well_formed) ok = false;
    if (list.count_written) {
      if (n != count) ok = false;
    } else {
      count = n;
    }
  }
  template <class Items, class Element>
  void columns(const ListInfo& list, std::uint32_t& count, std::size_t max_count, Items& items,
               Element element) {
    const std::size_t members = member_count(items[0], element);
    for (std::size_t k = 0; k < members; ++k) {
      const std::uint32_t number = next++;
      bool present = false;
      FieldRef f;
      if (!find_last(message, number, present, f) || (present && f.wire != kLen)) {
        ok = false;
        return;
      }
      Cursor c{f.payload};
      if (!list.count_written && k == 0) {
        // The first column's length is the count.
        std::uint32_t n = 0;
        Cursor counter{f.payload};
        while (counter.ok && !counter.at_end() && n <= max_count) {
          MemberIo io{[&](std::size_t index, std::string_view, const auto& v) {
            if (index == 0) (void)read_value<std::remove_cvref_t<decltype(v)>>(counter);
          }};
          element(io, items[0]);
          ++n;
        }
        count = n;
      }
      if (count > max_count) {
        ok = false;
        return;
      }
      for (std::uint32_t i = 0; i < count; ++i) {
        MemberIo io{[&](std::size_t index, std::string_view, auto& v) {
          if (index != k) return;
          const std::uint64_t raw = read_value<std::remove_cvref_t<decltype(v)>>(c);
          if (!c.ok || !set_value(raw, v)) ok = false;
        }};
        element(io, items[i]);
      }
      if (!c.ok || !c.at_end()) ok = false;
    }
  }
  template <class Setter>
  void text(std::string_view /*name*/, Setter set) {
    bool present = false;
    FieldRef f;
    if (!find_last(message, next++, present, f) || (present && f.wire != kLen)) {
      ok = false;
      return;
    }
    if (present) {
      set(std::string_view(reinterpret_cast<const char*>(f.payload.data()), f.payload.size()));
    }
  }
};

// A default message of each type, copied over the output before a decode: absent fields read as
// defaults even into a reused message. Function-local statics: a scan is 64 KiB.
template <class T>
const T& default_message() {
  static const auto m = std::make_unique<const T>();
  return *m;
}

// ---- descriptors ------------------------------------------------------------------------------

struct FieldDesc {
  std::string name;
  std::uint32_t number = 0;
  bool repeated = false;
  std::uint8_t type = 0;
  std::string type_name;  // fully qualified, for messages
};
struct MessageDesc {
  std::string name;
  std::vector<FieldDesc> fields;
  std::vector<MessageDesc> nested;
};

struct ProtoDescribeIo {
  static constexpr bool kReads = false;
  MessageDesc& message;
  std::string scope;  // ".coxswain.Tick" for the Tick message
  std::uint32_t next = 1;

  template <class T>
  void field(std::string_view name, const T& /*v*/, std::string_view /*note*/ = {}) {
    if constexpr (IsStdArray<T>::value) {
      message.fields.push_back(
          {std::string(name), next++, true, proto_type<typename T::value_type>(), {}});
    } else {
      message.fields.push_back({std::string(name), next++, false, proto_type<T>(), {}});
    }
  }
  template <class T>
  void since(std::uint8_t /*first_version*/, std::string_view name, const T& v) {
    field(name, v);
  }
  template <class Items, class Element>
  void elements(const ListInfo& list, std::uint32_t /*count*/, std::size_t /*max_count*/,
                const Items& items, Element element) {
    MessageDesc nested{std::string(list.type), {}, {}};
    const std::string type_name = scope + "." + std::string(list.type);
    ProtoDescribeIo io{nested, type_name};
    element(io, items[0]);
    message.nested.push_back(std::move(nested));
    message.fields.push_back({std::string(list.field), next++, true, kTypeMessage, type_name});
  }
  // Each member of a column list is a repeated scalar field of its own.
  template <class Items, class Element>
  void columns(const ListInfo& /*list*/, std::uint32_t /*count*/, std::size_t /*max_count*/,
               const Items& items, Element element) {
    MemberIo io{[this](std::size_t, std::string_view name, const auto& v) {
      message.fields.push_back(
          {std::string(name), next++, true, proto_type<std::remove_cvref_t<decltype(v)>>(), {}});
    }};
    element(io, items[0]);
  }
  void text(std::string_view name, std::string_view /*value*/, std::size_t /*max_len*/) {
    message.fields.push_back({std::string(name), next++, false, kTypeString, {}});
  }
};

const std::string kScope = ".coxswain";

FieldDesc scalar(std::string name, std::uint32_t number, std::uint8_t type) {
  return {std::move(name), number, false, type, {}};
}
FieldDesc message_field(std::string name, std::uint32_t number, std::string type_name,
                        bool repeated = false) {
  return {std::move(name), number, repeated, kTypeMessage, std::move(type_name)};
}

// A channel message: store_sequence, then the message's fields.
template <class T>
MessageDesc channel_message(const std::string& name) {
  MessageDesc d{name, {scalar("store_sequence", 1, kTypeUint64)}, {}};
  ProtoDescribeIo io{d, kScope + "." + name, 2};
  fields(io, default_message<T>());
  return d;
}

// A sample as the tick saw it: its store sequence and store stamp (named apart from the
// message's own `stamp_ns` and the IMU's `sequence`), then the message's fields.
template <class T>
MessageDesc tick_sample(const std::string& name) {
  MessageDesc d{
      name,
      {scalar("store_sequence", 1, kTypeUint64), scalar("store_stamp_ns", 2, kTypeSint64)},
      {}};
  ProtoDescribeIo io{d, kScope + ".Tick." + name, 3};
  if constexpr (std::is_same_v<T, msg::LidarScan>) {
    lidar_header_fields(io, default_message<T>());
  } else {
    fields(io, default_message<T>());
  }
  return d;
}

std::vector<MessageDesc> all_messages() {
  std::vector<MessageDesc> m;
  m.push_back({"RawBytes",
               {scalar("device", 1, kTypeUint32), scalar("direction", 2, kTypeUint32),
                scalar("stamp_ns", 3, kTypeSint64), scalar("data", 4, kTypeBytes)},
               {}});
  {
    MessageDesc command{"ActuatorCommand", {}, {}};
    ProtoDescribeIo io{command, kScope + ".ActuatorCommand"};
    fields(io, default_message<msg::ActuatorCommand>());
    m.push_back(std::move(command));
  }
  const std::string tick = kScope + ".Tick.";
  m.push_back(
      {"Tick",
       {scalar("tick_index", 1, kTypeUint64), scalar("now_ns", 2, kTypeSint64),
        message_field("command", 3, kScope + ".ActuatorCommand"),
        scalar("state_path", 4, kTypeString), message_field("lidar", 5, tick + "Lidar"),
        message_field("imu", 6, tick + "Imu"), message_field("gnss", 7, tick + "Gnss"),
        message_field("camera", 8, tick + "Camera"), message_field("arduino", 9, tick + "Arduino"),
        message_field("operator_input", 10, tick + "Operator"),
        message_field("health", 11, tick + "Health", true)},
       {tick_sample<msg::LidarScan>("Lidar"), tick_sample<msg::ImuSample>("Imu"),
        tick_sample<msg::GnssFix>("Gnss"), tick_sample<msg::CameraDetections>("Camera"),
        tick_sample<msg::ArduinoStatus>("Arduino"), tick_sample<msg::OperatorInput>("Operator"),
        tick_sample<msg::DeviceHealth>("Health")}});
  m.push_back(channel_message<msg::GnssFix>("GnssFix"));
  m.push_back(channel_message<msg::ImuSample>("ImuSample"));
  m.push_back(channel_message<msg::LidarScan>("LidarScan"));
  m.push_back(channel_message<msg::CameraDetections>("CameraDetections"));
  m.push_back(channel_message<msg::ArduinoStatus>("ArduinoStatus"));
  m.push_back(channel_message<msg::OperatorInput>("OperatorInput"));
  m.push_back(channel_message<msg::DeviceHealth>("DeviceHealth"));
  m.push_back({"ParameterSet",
               {scalar("tick_index", 1, kTypeUint64), scalar("stamp_ns", 2, kTypeSint64),
                message_field("values", 3, kScope + ".ParameterSet.Value", true)},
               {{"Value", {scalar("name", 1, kTypeString), scalar("value", 2, kTypeDouble)}, {}}}});
  return m;
}

// Hand-serialized descriptor.proto messages (descriptor.proto is itself protobuf).
void put_key(std::string& out, std::uint32_t number, Wire wire) {
  std::uint64_t v = (static_cast<std::uint64_t>(number) << 3) | wire;
  while (v >= 0x80) {
    out += static_cast<char>(v | 0x80);
    v >>= 7;
  }
  out += static_cast<char>(v);
}
void put_varint_field(std::string& out, std::uint32_t number, std::uint64_t v) {
  put_key(out, number, kVarint);
  while (v >= 0x80) {
    out += static_cast<char>(v | 0x80);
    v >>= 7;
  }
  out += static_cast<char>(v);
}
void put_bytes_field(std::string& out, std::uint32_t number, std::string_view payload) {
  put_key(out, number, kLen);
  std::uint64_t n = payload.size();
  while (n >= 0x80) {
    out += static_cast<char>(n | 0x80);
    n >>= 7;
  }
  out += static_cast<char>(n);
  out += payload;
}

std::string serialize(const MessageDesc& m) {
  std::string out;
  put_bytes_field(out, 1, m.name);  // DescriptorProto.name
  for (const FieldDesc& f : m.fields) {
    std::string field;
    put_bytes_field(field, 1, f.name);               // name
    put_varint_field(field, 3, f.number);            // number
    put_varint_field(field, 4, f.repeated ? 3 : 1);  // label: LABEL_REPEATED / LABEL_OPTIONAL
    put_varint_field(field, 5, f.type);              // type
    if (!f.type_name.empty()) put_bytes_field(field, 6, f.type_name);
    put_bytes_field(out, 2, field);  // DescriptorProto.field
  }
  for (const MessageDesc& n : m.nested) put_bytes_field(out, 3, serialize(n));  // nested_type
  return out;
}

void render(const MessageDesc& m, int indent, std::string& out) {
  const std::string pad(static_cast<std::size_t>(indent), ' ');
  out += pad + "message " + m.name + " {\n";
  for (const MessageDesc& n : m.nested) render(n, indent + 2, out);
  for (const FieldDesc& f : m.fields) {
    out += pad + "  ";
    if (f.repeated) out += "repeated ";
    out += f.type == kTypeMessage ? f.type_name : std::string(proto_type_name(f.type));
    out += " " + f.name + " = " + std::to_string(f.number) + ";\n";
  }
  out += pad + "}\n";
}

// ---- tick helpers -----------------------------------------------------------------------------

template <class T>
void put_tick_sample(Sink& s, std::uint32_t number, const core::Sample<T>& sample) {
  auto body = [&](Sink& out) {
    put_field(out, 1, sample.sequence);
    put_field(out, 2, sample.stamp_ns);
    ProtoWriteIo io{out, 3};
    if constexpr (std::is_same_v<T, msg::LidarScan>) {
      lidar_header_fields(io, sample.value);
    } else {
      fields(io, sample.value);
    }
  };
  Sink sizer({});
  body(sizer);
  s.tag(number, kLen);
  s.varint(sizer.size());
  body(s);
}

template <class T>
bool read_tick_sample(std::span<const std::uint8_t> payload, core::Sample<T>& sample) {
  ProtoReadIo io{payload, 3};
  if (!get_field(payload, 1, sample.sequence) || !get_field(payload, 2, sample.stamp_ns)) {
    return false;
  }
  if constexpr (std::is_same_v<T, msg::LidarScan>) {
    lidar_header_fields(io, sample.value);
    if (sample.value.point_count > msg::LidarScan::kMaxPoints) return false;
  } else {
    fields(io, sample.value);
  }
  return io.ok;
}

template <class T>
bool get_tick_sample(std::span<const std::uint8_t> message, std::uint32_t number,
                     core::Sample<T>& sample) {
  bool present = false;
  FieldRef f;
  if (!find_last(message, number, present, f)) return false;
  if (!present) return true;
  return f.wire == kLen && read_tick_sample(f.payload, sample);
}

const core::Snapshot& default_snapshot() { return default_message<core::Snapshot>(); }

}  // namespace

bool encoding_of(std::string_view message_encoding, Encoding& out) {
  if (message_encoding == kProtobufEncoding) {
    out = Encoding::kProtobuf;
    return true;
  }
  if (message_encoding == kBinaryMessageEncoding) {
    out = Encoding::kLegacyBinary;
    return true;
  }
  return false;
}

const std::string& file_descriptor_set(Layout layout) {
  // Each schema record carries only the types its message needs (the tick also needs the
  // command), so the descriptors cost a recording a few KiB, not ten copies of every type.
  static const std::array<std::string, kLayoutCount> sets = [] {
    const std::vector<MessageDesc> messages = all_messages();
    std::array<std::string, kLayoutCount> out;
    for (std::size_t i = 0; i < kLayoutCount; ++i) {
      const auto l = static_cast<Layout>(i);
      const std::string_view full_name = proto_message_name(l);
      const std::string_view name = full_name.substr(kProtoPackage.size() + 1);
      std::string file;
      put_bytes_field(file, 1, "coxswain/" + std::string(name) + ".proto");  // name
      put_bytes_field(file, 2, kProtoPackage);                               // package
      for (const MessageDesc& m : messages) {
        if (m.name == name || (l == Layout::kTick && m.name == "ActuatorCommand")) {
          put_bytes_field(file, 4, serialize(m));  // message_type
        }
      }
      put_bytes_field(file, 12, "proto3");  // syntax
      put_bytes_field(out[i], 1, file);     // FileDescriptorSet.file
    }
    return out;
  }();
  return sets[static_cast<std::size_t>(layout)];
}

const std::string& recording_proto_text() {
  static const std::string text = [] {
    std::string out = "syntax = \"proto3\";\npackage coxswain;\n";
    for (const MessageDesc& m : all_messages()) {
      out += "\n";
      render(m, 0, out);
    }
    return out;
  }();
  return text;
}

std::string_view proto_message_name(Layout layout) { return layout_schema_name(layout); }

namespace proto {

template <class T>
std::size_t encode_sample(std::span<std::uint8_t> out, std::uint64_t sequence, const T& m) {
  Sink s(out);
  put_field(s, 1, sequence);
  ProtoWriteIo io{s, 2};
  fields(io, m);
  return finish(s);
}

template <class T>
bool decode_sample(std::span<const std::uint8_t> in, std::uint64_t& sequence, T& m) {
  m = default_message<T>();
  sequence = 0;
  if (!get_field(in, 1, sequence)) return false;
  ProtoReadIo io{in, 2};
  fields(io, m);
  return io.ok;
}

// Every decoded-message type the recorder writes.
template std::size_t encode_sample<msg::GnssFix>(std::span<std::uint8_t>, std::uint64_t,
                                                 const msg::GnssFix&);
template bool decode_sample<msg::GnssFix>(std::span<const std::uint8_t>, std::uint64_t&,
                                          msg::GnssFix&);
template std::size_t encode_sample<msg::ImuSample>(std::span<std::uint8_t>, std::uint64_t,
                                                   const msg::ImuSample&);
template bool decode_sample<msg::ImuSample>(std::span<const std::uint8_t>, std::uint64_t&,
                                            msg::ImuSample&);
template std::size_t encode_sample<msg::LidarScan>(std::span<std::uint8_t>, std::uint64_t,
                                                   const msg::LidarScan&);
template bool decode_sample<msg::LidarScan>(std::span<const std::uint8_t>, std::uint64_t&,
                                            msg::LidarScan&);
template std::size_t encode_sample<msg::CameraDetections>(std::span<std::uint8_t>, std::uint64_t,
                                                          const msg::CameraDetections&);
template bool decode_sample<msg::CameraDetections>(std::span<const std::uint8_t>, std::uint64_t&,
                                                   msg::CameraDetections&);
template std::size_t encode_sample<msg::ArduinoStatus>(std::span<std::uint8_t>, std::uint64_t,
                                                       const msg::ArduinoStatus&);
template bool decode_sample<msg::ArduinoStatus>(std::span<const std::uint8_t>, std::uint64_t&,
                                                msg::ArduinoStatus&);
template std::size_t encode_sample<msg::OperatorInput>(std::span<std::uint8_t>, std::uint64_t,
                                                       const msg::OperatorInput&);
template bool decode_sample<msg::OperatorInput>(std::span<const std::uint8_t>, std::uint64_t&,
                                                msg::OperatorInput&);
template std::size_t encode_sample<msg::DeviceHealth>(std::span<std::uint8_t>, std::uint64_t,
                                                      const msg::DeviceHealth&);
template bool decode_sample<msg::DeviceHealth>(std::span<const std::uint8_t>, std::uint64_t&,
                                               msg::DeviceHealth&);

std::size_t encode_tick(std::span<std::uint8_t> out, std::uint64_t tick_index, core::TimeNs now_ns,
                        const core::Snapshot& snapshot, const msg::ActuatorCommand& command,
                        std::string_view state_path) {
  Sink s(out);
  put_field(s, 1, tick_index);
  put_field(s, 2, now_ns);
  put_message(s, 3, command);
  ProtoWriteIo path{s, 4};
  path.text("state_path", state_path, kMaxStatePathBytes);
  // Lidar: the sample header only; the points travel once in /lidar under the same sequence.
  put_tick_sample(s, 5, snapshot.lidar);
  put_tick_sample(s, 6, snapshot.imu);
  put_tick_sample(s, 7, snapshot.gnss);
  put_tick_sample(s, 8, snapshot.camera);
  put_tick_sample(s, 9, snapshot.arduino);
  put_tick_sample(s, 10, snapshot.operator_input);
  for (const auto& h : snapshot.health) put_tick_sample(s, 11, h);
  return finish(s);
}

bool decode_tick(std::span<const std::uint8_t> in, TickRecordData& out) {
  out.snapshot = default_snapshot();
  out.command = default_message<msg::ActuatorCommand>();
  out.tick_index = 0;
  out.now_ns = 0;
  out.state_path.clear();
  if (!get_field(in, 1, out.tick_index) || !get_field(in, 2, out.now_ns)) return false;
  bool present = false;
  FieldRef f;
  if (!find_last(in, 3, present, f)) return false;
  if (present) {
    if (f.wire != kLen) return false;
    ProtoReadIo io{f.payload};
    fields(io, out.command);
    if (!io.ok) return false;
  }
  ProtoReadIo path{in, 4};
  path.text("state_path", [&](std::string_view s) { out.state_path = std::string(s); });
  if (!path.ok || out.state_path.size() > kMaxStatePathBytes) return false;
  core::Snapshot& snap = out.snapshot;
  if (!get_tick_sample(in, 5, snap.lidar) || !get_tick_sample(in, 6, snap.imu) ||
      !get_tick_sample(in, 7, snap.gnss) || !get_tick_sample(in, 8, snap.camera) ||
      !get_tick_sample(in, 9, snap.arduino) || !get_tick_sample(in, 10, snap.operator_input)) {
    return false;
  }
  std::size_t n = 0;
  bool ok = true;
  const bool well_formed = for_each_occurrence(in, 11, [&](const FieldRef& h) {
    if (h.wire != kLen || n >= snap.health.size() || !read_tick_sample(h.payload, snap.health[n])) {
      ok = false;
      return;
    }
    ++n;
  });
  return well_formed && ok;
}

std::size_t encode_raw(std::span<std::uint8_t> out, const RawRecord& raw) {
  Sink s(out);
  put_field(s, 1, static_cast<std::uint32_t>(raw.device));
  put_field(s, 2, static_cast<std::uint32_t>(raw.direction));
  put_field(s, 3, raw.stamp_ns);
  s.tag(4, kLen);
  s.varint(raw.bytes.size());
  s.bytes(raw.bytes);
  return finish(s);
}

bool decode_raw(std::span<const std::uint8_t> in, RawRecord& raw) {
  std::uint32_t device = 0;
  std::uint32_t direction = 0;
  raw.stamp_ns = 0;
  raw.bytes = {};
  bool present = false;
  FieldRef f;
  if (!get_field(in, 1, device) || !get_field(in, 2, direction) ||
      !get_field(in, 3, raw.stamp_ns) || !find_last(in, 4, present, f)) {
    return false;
  }
  if (present) {
    if (f.wire != kLen) return false;
    raw.bytes = f.payload;
  }
  if (device >= msg::kDeviceCount || direction > 1) return false;
  raw.device = static_cast<msg::DeviceId>(device);
  raw.direction = static_cast<drivers::RawDirection>(direction);
  return true;
}

std::size_t encode_parameters(std::span<std::uint8_t> out, std::uint64_t tick_index,
                              core::TimeNs stamp_ns, std::span<const NamedValue> values) {
  Sink s(out);
  put_field(s, 1, tick_index);
  put_field(s, 2, stamp_ns);
  for (const NamedValue& v : values) {
    if (v.name.size() > 0xFF) return 0;
    auto body = [&](Sink& o) {
      o.tag(1, kLen);
      o.varint(v.name.size());
      o.bytes(std::span(reinterpret_cast<const std::uint8_t*>(v.name.data()), v.name.size()));
      put_field(o, 2, v.value);
    };
    Sink sizer({});
    body(sizer);
    s.tag(3, kLen);
    s.varint(sizer.size());
    body(s);
  }
  return finish(s);
}

bool decode_parameters(std::span<const std::uint8_t> in, ParameterSetRecord& out) {
  out = {};
  if (!get_field(in, 1, out.tick_index) || !get_field(in, 2, out.stamp_ns)) return false;
  bool ok = true;
  const bool well_formed = for_each_occurrence(in, 3, [&](const FieldRef& f) {
    if (f.wire != kLen) {
      ok = false;
      return;
    }
    double value = 0.0;
    bool present = false;
    FieldRef name;
    if (!find_last(f.payload, 1, present, name) || (present && name.wire != kLen) ||
        !get_field(f.payload, 2, value) || name.payload.size() > 0xFF) {
      ok = false;
      return;
    }
    out.values.emplace_back(
        std::string(reinterpret_cast<const char*>(name.payload.data()), name.payload.size()),
        value);
  });
  return well_formed && ok;
}

}  // namespace proto

bool decode_tick(Encoding encoding, std::span<const std::uint8_t> in, TickRecordData& out) {
  return encoding == Encoding::kProtobuf ? proto::decode_tick(in, out) : decode_tick(in, out);
}
bool decode_raw(Encoding encoding, std::span<const std::uint8_t> in, RawRecord& raw) {
  return encoding == Encoding::kProtobuf ? proto::decode_raw(in, raw) : decode_raw(in, raw);
}
bool decode_parameters(Encoding encoding, std::span<const std::uint8_t> in,
                       ParameterSetRecord& out) {
  return encoding == Encoding::kProtobuf ? proto::decode_parameters(in, out)
                                         : decode_parameters(in, out);
}

bool peek_sequence(Encoding encoding, std::span<const std::uint8_t> in, std::uint64_t& sequence) {
  sequence = 0;
  if (encoding == Encoding::kProtobuf) return get_field(in, 1, sequence);
  ByteReader r(in);
  (void)r.u8();  // layout version
  sequence = r.u64();
  return !r.underrun();
}

}  // namespace coxswain::record
