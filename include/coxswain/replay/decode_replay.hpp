// SPDX-License-Identifier: Apache-2.0
#pragma once
// `coxswain replay --decode RUN.mcap`: re-runs today's pure device codecs on a recording's raw
// bytes (/raw/<device>, direction from-device) and counts what they produce and reject, beside
// the number of decoded messages the run itself recorded (/gnss, /imu, /lidar, /arduino). Used
// to check a codec change against past runs. Thread-safety: none needed (pure functions).
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "coxswain/drivers/myahrs/heading.hpp"
#include "coxswain/drivers/rplidar/scan_assembler.hpp"
#include "coxswain/msg/device_health.hpp"
#include "coxswain/record/mcap_reader.hpp"

namespace coxswain::replay {

struct DecodeReplayOptions {
  drivers::rplidar::ScanAssemblerParams lidar;  // mount and range limits from boat.yaml
  drivers::myahrs::HeadingConfig imu;           // mount yaw and declination
};

struct DeviceDecodeCounts {
  msg::DeviceId device = msg::DeviceId::kLidar;
  std::uint64_t raw_messages = 0;
  std::uint64_t bytes_from_device = 0;
  std::uint64_t bytes_to_device = 0;
  /// What the codec turned the bytes into: lidar revolutions (scans), IMU samples, GNSS fixes,
  /// Arduino telemetry frames. The camera has no byte codec (always 0).
  std::uint64_t decoded = 0;
  std::uint64_t frames_ok = 0;
  std::uint64_t checksum_errors = 0;
  std::uint64_t framing_errors = 0;
  std::uint64_t bytes_skipped = 0;
  /// Messages of the matching decoded channel in the recording (what the run published and the
  /// recorder sampled), when the recording has that channel.
  std::optional<std::uint64_t> recorded;
};

struct DecodeReplayReport {
  bool ok = false;  // the file was read (possibly truncated)
  std::string error;
  record::McapReadReport file;
  std::vector<DeviceDecodeCounts> devices;  // one per device, msg::DeviceId order
};

[[nodiscard]] DecodeReplayReport decode_replay(const std::filesystem::path& mcap,
                                               const DecodeReplayOptions& options = {});
/// A human-readable table of the report (one line per device).
[[nodiscard]] std::string format_decode_replay(const DecodeReplayReport& report);

}  // namespace coxswain::replay
