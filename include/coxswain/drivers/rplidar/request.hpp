// SPDX-License-Identifier: Apache-2.0
#pragma once
// RPLIDAR request encoder (host -> lidar), docs/protocols.md 1.2-1.3: `A5 cmd` for commands below
// 0x80, `A5 cmd N payload[N] xor` otherwise, xor = XOR of every preceding byte. Pure functions,
// fixed-size result, no allocation.
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>

#include "coxswain/drivers/rplidar/protocol.hpp"

namespace coxswain::drivers::rplidar {

/// One encoded request plus the answer the decoder should be told to expect after sending it.
struct Request {
  static constexpr std::size_t kMaxPayload = 12;
  static constexpr std::size_t kMaxSize = 3 + kMaxPayload + 1;

  std::array<std::uint8_t, kMaxSize> bytes{};
  std::uint8_t size = 0;
  /// Answer type the lidar replies with; nullopt for commands without an answer.
  std::optional<AnswerType> answer;
  /// Milliseconds the host should wait before the next request (manual: STOP 1 ms, RESET 2 ms;
  /// the SDK sleeps longer and the adapter may too).
  std::uint16_t settle_ms = 0;

  [[nodiscard]] std::span<const std::uint8_t> span() const { return {bytes.data(), size}; }
};

/// Generic encoder. Payload is only sent for commands >= 0x80; returns nullopt if a payload is
/// given to a short command or the payload is longer than Request::kMaxPayload.
[[nodiscard]] std::optional<Request> encode_request(std::uint8_t command,
                                                    std::span<const std::uint8_t> payload);

[[nodiscard]] Request encode_stop();
[[nodiscard]] Request encode_reset();
[[nodiscard]] Request encode_scan();
[[nodiscard]] Request encode_force_scan();
/// EXPRESS_SCAN with working mode `mode` (0 = legacy express). `answer` is the mode's answer
/// type from SCAN_MODE_ANS_TYPE (0x82 legacy, 0x84 ultra, 0x85 dense).
[[nodiscard]] Request encode_express_scan(std::uint8_t mode,
                                          AnswerType answer = AnswerType::kCapsule);
[[nodiscard]] Request encode_get_info();
[[nodiscard]] Request encode_get_health();
[[nodiscard]] Request encode_get_sample_rate();
/// GET_LIDAR_CONF with u32 type and, for per-mode types, the u16 scan mode id.
[[nodiscard]] Request encode_get_lidar_conf(ConfType type,
                                            std::optional<std::uint16_t> scan_mode = std::nullopt);
[[nodiscard]] Request encode_get_lidar_conf_raw(std::uint32_t type,
                                                std::optional<std::uint16_t> scan_mode);
/// SET_MOTOR_PWM, pwm clamped to 0..1023 (A2/A3 accessory board).
[[nodiscard]] Request encode_set_motor_pwm(std::uint16_t pwm);
/// HQ_MOTOR_SPEED_CTRL (S series), motor speed in rpm.
[[nodiscard]] Request encode_hq_motor_speed(std::uint16_t rpm);
[[nodiscard]] Request encode_get_acc_board_flag();

inline constexpr std::uint16_t kMaxMotorPwm = 1023;
inline constexpr std::uint16_t kDefaultMotorPwm = 660;
inline constexpr std::uint16_t kDefaultMotorRpm = 600;

}  // namespace coxswain::drivers::rplidar
