// SPDX-License-Identifier: Apache-2.0
#pragma once
// `coxswain decode`: turns a raw capture of one device (capture mode's DIR/<device>.raw, or any
// recording of the bytes the device sent) into one JSON object per decoded message, using the
// production codecs. Units are in the field names.
//
// RPLIDAR: the codec needs to know what answer it is cutting (standard nodes or a capsule
// format), which only the response descriptor (A5 5A len|mode type) says. The capture must
// therefore contain the descriptors, as a capture made from the port's opening does (the start
// sequence's answers and the scan's descriptor): the decoder accepts any descriptor and follows
// the answer mode it announces. Bytes before the first descriptor are skipped and counted.
//
// myAHRS+: heading_deg is the sensor yaw with no mount yaw and no declination applied.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <iosfwd>
#include <memory>
#include <optional>
#include <span>
#include <string_view>

#include <nlohmann/json.hpp>

namespace coxswain::app {

enum class CaptureFormat : std::uint8_t { kRplidar, kMyahrs, kUblox, kArduino };

/// "rplidar", "myahrs", "ublox" or "arduino".
[[nodiscard]] std::optional<CaptureFormat> parse_capture_format(std::string_view name);
[[nodiscard]] std::string_view capture_format_name(CaptureFormat format);

/// Decodes a capture fed in pieces of any size. Every message is passed to `emit` as a JSON
/// object with "type" and "end_offset_bytes" (the offset just past the byte that completed it).
/// Not thread-safe.
class CaptureDecoder {
 public:
  using Emit = std::function<void(const nlohmann::json&)>;

  explicit CaptureDecoder(CaptureFormat format);
  ~CaptureDecoder();
  CaptureDecoder(const CaptureDecoder&) = delete;
  CaptureDecoder& operator=(const CaptureDecoder&) = delete;

  void feed(std::span<const std::uint8_t> bytes, const Emit& emit);
  /// End of input: delivers frames a codec held back after a resync.
  void finish(const Emit& emit);
  /// {"summary": true, "device", "bytes", "messages", and the codec's error counters}.
  [[nodiscard]] nlohmann::json summary() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Decodes the file at `path`: one JSON line per message on `out`, then the summary line.
/// Returns 0, or 1 (with a message on `err`) when the file cannot be read.
int decode_capture_file(CaptureFormat format, const std::filesystem::path& path, std::ostream& out,
                        std::ostream& err);

}  // namespace coxswain::app
