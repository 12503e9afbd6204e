// SPDX-License-Identifier: Apache-2.0
#pragma once
// The recording's messages in protobuf (proto3 wire format), so every channel of a recording
// decodes in Foxglove, Lichtblick or any protobuf library: each channel's MCAP Schema record
// holds a FileDescriptorSet describing its message (`file_descriptor_set()`), and the message
// types follow the same field lists as the legacy packed layouts (layouts.hpp), a field's number
// being its position in its list. `recording_proto_text()` is the same description as .proto
// source (src/record/FORMAT.md quotes it).
//
// Recordings written before protobuf use the packed layouts ("coxswain-binary"); the decoders
// below that take an `Encoding` read both, so old recordings still replay.
//
// Encoders write into caller buffers and never allocate (the tick thread encodes); a nested
// message's length is found by encoding it once into no buffer first.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "coxswain/record/layouts.hpp"

namespace coxswain::record {

/// How a channel's messages are encoded.
enum class Encoding : std::uint8_t { kLegacyBinary, kProtobuf };

/// MCAP message and schema encoding of the protobuf channels.
inline constexpr std::string_view kProtobufEncoding = "protobuf";
/// The .proto package of every message type.
inline constexpr std::string_view kProtoPackage = "coxswain";

/// The encoding an MCAP channel's message encoding names ("protobuf", or "coxswain-binary" for
/// the legacy layouts). False when it is neither.
[[nodiscard]] bool encoding_of(std::string_view message_encoding, Encoding& out);

/// Serialized google.protobuf.FileDescriptorSet for a layout's channel: one file
/// ("coxswain/<Type>.proto") with the message type and the types it uses. Built once.
[[nodiscard]] const std::string& file_descriptor_set(Layout layout);
/// The same messages as .proto source.
[[nodiscard]] const std::string& recording_proto_text();
/// The fully qualified message type of a layout's channel ("coxswain.Tick", ...).
[[nodiscard]] std::string_view proto_message_name(Layout layout);

namespace proto {

/// Upper bounds of encoded messages (checked by tests).
inline constexpr std::size_t kMaxTickBytes = 4096;
inline constexpr std::size_t kMaxLidarBytes = 128 + msg::LidarScan::kMaxPoints * 16;
inline constexpr std::size_t kMaxParameterBytes = 16384;
inline constexpr std::size_t kMaxRawOverheadBytes = 32;

/// Bytes written, 0 when `out` is too small.
template <class T>
std::size_t encode_sample(std::span<std::uint8_t> out, std::uint64_t sequence, const T& m);
template <class T>
bool decode_sample(std::span<const std::uint8_t> in, std::uint64_t& sequence, T& m);

std::size_t encode_tick(std::span<std::uint8_t> out, std::uint64_t tick_index, core::TimeNs now_ns,
                        const core::Snapshot& snapshot, const msg::ActuatorCommand& command,
                        std::string_view state_path);
bool decode_tick(std::span<const std::uint8_t> in, TickRecordData& out);

std::size_t encode_raw(std::span<std::uint8_t> out, const RawRecord& raw);
bool decode_raw(std::span<const std::uint8_t> in, RawRecord& raw);

std::size_t encode_parameters(std::span<std::uint8_t> out, std::uint64_t tick_index,
                              core::TimeNs stamp_ns, std::span<const NamedValue> values);
bool decode_parameters(std::span<const std::uint8_t> in, ParameterSetRecord& out);

}  // namespace proto

// Decoders of either encoding (the channel's).
template <class T>
bool decode_sample(Encoding encoding, std::span<const std::uint8_t> in, std::uint64_t& sequence,
                   T& m) {
  return encoding == Encoding::kProtobuf ? proto::decode_sample(in, sequence, m)
                                         : decode_sample(in, sequence, m);
}
bool decode_tick(Encoding encoding, std::span<const std::uint8_t> in, TickRecordData& out);
bool decode_raw(Encoding encoding, std::span<const std::uint8_t> in, RawRecord& raw);
bool decode_parameters(Encoding encoding, std::span<const std::uint8_t> in,
                       ParameterSetRecord& out);
/// The store sequence of a decoded-message channel's message, without decoding the rest.
bool peek_sequence(Encoding encoding, std::span<const std::uint8_t> in, std::uint64_t& sequence);

}  // namespace coxswain::record
