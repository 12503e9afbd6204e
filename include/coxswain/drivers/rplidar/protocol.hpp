// SPDX-License-Identifier: Apache-2.0
#pragma once
// Slamtec RPLIDAR serial protocol: constants, answer payload structs, the SDK's "HQ node" sample
// form and the per-model table. Protocol reference: docs/protocols.md section 1 (facts from
// Slamtec/rplidar_sdk sl_lidar_cmd.h / sl_lidar_protocol.h and the protocol manual).
#include <array>
#include <cstddef>
#include <cstdint>
#include <string_view>

namespace coxswain::drivers::rplidar {

/// Request command bytes (docs/protocols.md 1.3).
enum class Command : std::uint8_t {
  kStop = 0x25,
  kReset = 0x40,
  kScan = 0x20,
  kForceScan = 0x21,
  kExpressScan = 0x82,
  kGetInfo = 0x50,
  kGetHealth = 0x52,
  kGetSampleRate = 0x59,
  kGetLidarConf = 0x84,
  kHqMotorSpeedCtrl = 0xA8,
  kSetMotorPwm = 0xF0,
  kGetAccBoardFlag = 0xFF,
};

/// Answer data types carried in the response descriptor (docs/protocols.md 1.4).
enum class AnswerType : std::uint8_t {
  kDevInfo = 0x04,
  kHealth = 0x06,
  kSampleRate = 0x15,
  kLidarConf = 0x20,
  kMeasurement = 0x81,        // standard 5-byte node
  kCapsule = 0x82,            // express legacy capsule, 84 bytes
  kHqCapsule = 0x83,          // not decoded (1.10)
  kUltraCapsule = 0x84,       // 132 bytes
  kDenseCapsule = 0x85,       // 84 bytes
  kUltraDenseCapsule = 0x86,  // not decoded (1.10)
  kAccBoardFlag = 0xFF,
};

/// Send mode from the descriptor: one answer, or answers repeated until STOP/RESET.
enum class SendMode : std::uint8_t { kSingle = 0, kContinuous = 1 };

inline constexpr std::uint8_t kSyncByte1 = 0xA5;
inline constexpr std::uint8_t kSyncByte2 = 0x5A;
inline constexpr std::size_t kDescriptorSize = 7;
inline constexpr std::size_t kNodeSize = 5;
inline constexpr std::size_t kCapsuleSize = 84;
inline constexpr std::size_t kUltraCapsuleSize = 132;
inline constexpr std::size_t kDenseCapsuleSize = 84;
inline constexpr std::size_t kDevInfoSize = 20;
inline constexpr std::size_t kHealthSize = 3;
inline constexpr std::size_t kSampleRateSize = 4;
inline constexpr std::size_t kAccBoardFlagSize = 4;
/// Longest LIDAR_CONF answer kept (u32 type + data); longer ones are counted as framing errors.
inline constexpr std::size_t kMaxConfAnswerSize = 64;

/// GET_LIDAR_CONF types used by the start sequence (docs/protocols.md 1.5).
enum class ConfType : std::uint32_t {
  kDesiredRotFreq = 0x01,
  kScanModeCount = 0x70,
  kScanModeUsPerSample = 0x71,
  kScanModeMaxDistance = 0x74,
  kScanModeAnsType = 0x75,
  kScanModeTypical = 0x7C,
  kScanModeName = 0x7F,
};

/// One sample in the SDK's normalised form (sl_lidar_response_measurement_node_hq_t): every scan
/// mode is converted to this so test vectors compare bit for bit.
struct HqNode {
  std::uint16_t angle_z_q14 = 0;  // degrees = v * 90 / 16384, lidar's own angle [0, 360)
  std::uint32_t dist_mm_q2 = 0;   // millimetres = v / 4; 0 = no return
  std::uint8_t quality = 0;       // 0..255 (standard quality << 2; capsules 188 or 0)
  std::uint8_t flag = 0;          // bit0 = first sample of a new lidar revolution

  [[nodiscard]] bool start_of_scan() const { return (flag & 1U) != 0; }
  [[nodiscard]] double angle_deg() const { return angle_z_q14 * 90.0 / 16384.0; }
  [[nodiscard]] double distance_mm() const { return dist_mm_q2 / 4.0; }
  friend bool operator==(const HqNode&, const HqNode&) = default;
};

enum class Family : std::uint8_t { kUnknown, kA, kC, kS, kT, kM };
/// How the motor is started (docs/protocols.md 1.11).
enum class MotorControl : std::uint8_t {
  kDtr,         // A1 / no accessory board: clear DTR to spin, set DTR to stop
  kPwm,         // A2/A3 accessory board: SET_MOTOR_PWM
  kRpmCommand,  // S series: HQ_MOTOR_SPEED_CTRL
  kFirmware,    // motor managed by the lidar itself (C1, inferred; Ethernet units)
};

/// GET_INFO answer (type 0x04).
struct DeviceInfo {
  std::uint8_t model = 0;
  std::uint8_t firmware_major = 0;
  std::uint8_t firmware_minor = 0;
  std::uint8_t hardware = 0;
  std::array<std::uint8_t, 16> serial{};

  [[nodiscard]] std::uint8_t model_major() const { return static_cast<std::uint8_t>(model >> 4); }
  [[nodiscard]] std::uint8_t model_minor() const {
    return static_cast<std::uint8_t>(model & 0x0FU);
  }
  [[nodiscard]] std::uint16_t firmware() const {
    return static_cast<std::uint16_t>((firmware_major << 8) | firmware_minor);
  }
  friend bool operator==(const DeviceInfo&, const DeviceInfo&) = default;
};

/// What the driver needs to know about a model, derived from DEVINFO. Ranges are datasheet
/// defaults (config or GET_LIDAR_CONF MAX_DISTANCE may override them).
struct ModelInfo {
  Family family = Family::kUnknown;
  std::array<char, 8> name{};     // "A1M8", "S2M1", ... NUL-terminated
  std::uint32_t native_baud = 0;  // 0 = not a serial unit (T/M series)
  MotorControl motor = MotorControl::kDtr;
  /// True when the SDK asks GET_ACC_BOARD_FLAG to decide between DTR and PWM (A2/A3/C).
  bool query_acc_board = false;
  /// True when GET_LIDAR_CONF is supported (major >= 4 or firmware >= 1.24).
  bool supports_conf = false;
  /// True when GET_SAMPLERATE is supported (firmware >= 1.17 or a new-design unit).
  bool supports_sample_rate = false;
  float min_range_m = 0.15F;
  float max_range_m = 12.0F;

  [[nodiscard]] std::string_view name_view() const { return {name.data()}; }
};

[[nodiscard]] ModelInfo model_info(const DeviceInfo& info);

/// GET_HEALTH answer (type 0x06). Status 2 = error per the SDK (ArduPilot's 3 is wrong).
struct Health {
  enum class Status : std::uint8_t { kGood = 0, kWarning = 1, kError = 2 };
  std::uint8_t status = 0;
  std::uint16_t error_code = 0;
  [[nodiscard]] bool is_error() const { return status >= 2; }
  friend bool operator==(const Health&, const Health&) = default;
};

/// GET_SAMPLERATE answer (type 0x15), microseconds per sample.
struct SampleRate {
  std::uint16_t standard_us = 0;
  std::uint16_t express_us = 0;
  friend bool operator==(const SampleRate&, const SampleRate&) = default;
};

/// GET_LIDAR_CONF answer (type 0x20): echoed type plus raw data bytes.
struct LidarConf {
  std::uint32_t type = 0;
  std::uint8_t size = 0;  // bytes of data after the echoed type
  std::array<std::uint8_t, kMaxConfAnswerSize - 4> data{};

  /// Little-endian unsigned value of the first `bytes` (<= 4) data bytes; 0 if too short.
  [[nodiscard]] std::uint32_t as_uint(std::size_t bytes) const;
  /// Data as text (SCAN_MODE_NAME), stopping at the first NUL.
  [[nodiscard]] std::string_view as_text() const;
};

/// GET_ACC_BOARD_FLAG answer (type 0xFF).
struct AccBoardFlag {
  std::uint32_t flag = 0;
  [[nodiscard]] bool pwm_supported() const { return (flag & 1U) != 0; }
};

/// Standard node -> HQ node with the SDK's integer arithmetic (docs/protocols.md 1.6).
[[nodiscard]] constexpr HqNode hq_from_standard(std::uint8_t sync_quality,
                                                std::uint16_t angle_q6_checkbit,
                                                std::uint16_t distance_q2) {
  HqNode n;
  n.angle_z_q14 =
      static_cast<std::uint16_t>(((std::uint32_t{angle_q6_checkbit} >> 1U) << 8U) / 90U);
  n.dist_mm_q2 = distance_q2;
  n.flag = static_cast<std::uint8_t>(sync_quality & 1U);
  n.quality = static_cast<std::uint8_t>(sync_quality & 0xFCU);
  return n;
}

}  // namespace coxswain::drivers::rplidar
