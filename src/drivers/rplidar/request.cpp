// SPDX-License-Identifier: Apache-2.0
#include "coxswain/drivers/rplidar/request.hpp"

#include <algorithm>

#include "little_endian.hpp"

namespace coxswain::drivers::rplidar {
namespace {

constexpr std::uint8_t cmd_byte(Command c) { return static_cast<std::uint8_t>(c); }

// Commands used below are always well formed, so the optional always holds a value.
Request must(std::optional<Request> r) { return r.value_or(Request{}); }

Request with_answer(Request r, std::optional<AnswerType> answer, std::uint16_t settle_ms = 0) {
  r.answer = answer;
  r.settle_ms = settle_ms;
  return r;
}

Request simple(Command c, std::optional<AnswerType> answer, std::uint16_t settle_ms = 0) {
  return with_answer(must(encode_request(cmd_byte(c), {})), answer, settle_ms);
}

}  // namespace

std::optional<Request> encode_request(std::uint8_t command, std::span<const std::uint8_t> payload) {
  const bool has_payload = (command & 0x80U) != 0;
  if (!has_payload && !payload.empty()) return std::nullopt;
  if (payload.size() > Request::kMaxPayload) return std::nullopt;
  Request r;
  r.bytes[0] = kSyncByte1;
  r.bytes[1] = command;
  if (!has_payload) {
    r.size = 2;
    return r;
  }
  r.bytes[2] = static_cast<std::uint8_t>(payload.size());
  std::copy(payload.begin(), payload.end(), r.bytes.begin() + 3);
  const std::size_t n = 3 + payload.size();
  std::uint8_t x = 0;
  for (std::size_t i = 0; i < n; ++i) x = static_cast<std::uint8_t>(x ^ r.bytes[i]);
  r.bytes[n] = x;
  r.size = static_cast<std::uint8_t>(n + 1);
  return r;
}

Request encode_stop() { return simple(Command::kStop, std::nullopt, 1); }
Request encode_reset() { return simple(Command::kReset, std::nullopt, 2); }
Request encode_scan() { return simple(Command::kScan, AnswerType::kMeasurement); }
Request encode_force_scan() { return simple(Command::kForceScan, AnswerType::kMeasurement); }

Request encode_express_scan(std::uint8_t mode, AnswerType answer) {
  std::array<std::uint8_t, 5> p{};  // u8 working_mode, u16 working_flags 0, u16 param 0
  p[0] = mode;
  return with_answer(must(encode_request(cmd_byte(Command::kExpressScan), p)), answer);
}

Request encode_get_info() { return simple(Command::kGetInfo, AnswerType::kDevInfo); }
Request encode_get_health() { return simple(Command::kGetHealth, AnswerType::kHealth); }
Request encode_get_sample_rate() {
  return simple(Command::kGetSampleRate, AnswerType::kSampleRate);
}

Request encode_get_lidar_conf_raw(std::uint32_t type, std::optional<std::uint16_t> scan_mode) {
  std::array<std::uint8_t, 6> p{};
  put_u32(p.data(), type);
  std::size_t n = 4;
  if (scan_mode) {
    put_u16(p.data() + 4, *scan_mode);
    n = 6;
  }
  return with_answer(must(encode_request(cmd_byte(Command::kGetLidarConf), std::span(p.data(), n))),
                     AnswerType::kLidarConf);
}

Request encode_get_lidar_conf(ConfType type, std::optional<std::uint16_t> scan_mode) {
  return encode_get_lidar_conf_raw(static_cast<std::uint32_t>(type), scan_mode);
}

Request encode_set_motor_pwm(std::uint16_t pwm) {
  std::array<std::uint8_t, 2> p{};
  put_u16(p.data(), std::min(pwm, kMaxMotorPwm));
  return with_answer(must(encode_request(cmd_byte(Command::kSetMotorPwm), p)), std::nullopt);
}

Request encode_hq_motor_speed(std::uint16_t rpm) {
  std::array<std::uint8_t, 2> p{};
  put_u16(p.data(), rpm);
  return with_answer(must(encode_request(cmd_byte(Command::kHqMotorSpeedCtrl), p)), std::nullopt);
}

Request encode_get_acc_board_flag() {
  std::array<std::uint8_t, 4> p{};  // u32 reserved = 0
  return with_answer(must(encode_request(cmd_byte(Command::kGetAccBoardFlag), p)),
                     AnswerType::kAccBoardFlag);
}

}  // namespace coxswain::drivers::rplidar
