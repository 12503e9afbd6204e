// SPDX-License-Identifier: Apache-2.0
// Request encoder against the worked examples of docs/protocols.md 1.2 and the command table 1.3.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <vector>

#include "coxswain/drivers/rplidar/request.hpp"

namespace coxswain::drivers::rplidar {
namespace {

std::vector<std::uint8_t> bytes(const Request& r) { return {r.span().begin(), r.span().end()}; }
using V = std::vector<std::uint8_t>;

TEST(RplidarRequest, WorkedExamplesFromProtocolDoc) {
  EXPECT_EQ(bytes(encode_express_scan(0)), (V{0xA5, 0x82, 0x05, 0, 0, 0, 0, 0, 0x22}));
  EXPECT_EQ(bytes(encode_set_motor_pwm(660)), (V{0xA5, 0xF0, 0x02, 0x94, 0x02, 0xC1}));
  EXPECT_EQ(bytes(encode_hq_motor_speed(600)), (V{0xA5, 0xA8, 0x02, 0x58, 0x02, 0x55}));
  EXPECT_EQ(bytes(encode_get_acc_board_flag()), (V{0xA5, 0xFF, 0x04, 0, 0, 0, 0, 0x5E}));
  EXPECT_EQ(bytes(encode_get_lidar_conf(ConfType::kScanModeTypical)),
            (V{0xA5, 0x84, 0x04, 0x7C, 0, 0, 0, 0x59}));
}

TEST(RplidarRequest, ShortCommandsAreTwoBytes) {
  EXPECT_EQ(bytes(encode_stop()), (V{0xA5, 0x25}));
  EXPECT_EQ(bytes(encode_reset()), (V{0xA5, 0x40}));
  EXPECT_EQ(bytes(encode_scan()), (V{0xA5, 0x20}));
  EXPECT_EQ(bytes(encode_force_scan()), (V{0xA5, 0x21}));
  EXPECT_EQ(bytes(encode_get_info()), (V{0xA5, 0x50}));
  EXPECT_EQ(bytes(encode_get_health()), (V{0xA5, 0x52}));
  EXPECT_EQ(bytes(encode_get_sample_rate()), (V{0xA5, 0x59}));
}

TEST(RplidarRequest, ExpectedAnswersAndSettleTimes) {
  EXPECT_FALSE(encode_stop().answer.has_value());
  EXPECT_GE(encode_stop().settle_ms, 1);
  EXPECT_GE(encode_reset().settle_ms, 2);
  EXPECT_EQ(encode_scan().answer, AnswerType::kMeasurement);
  EXPECT_EQ(encode_get_info().answer, AnswerType::kDevInfo);
  EXPECT_EQ(encode_get_health().answer, AnswerType::kHealth);
  EXPECT_EQ(encode_get_sample_rate().answer, AnswerType::kSampleRate);
  EXPECT_EQ(encode_get_lidar_conf(ConfType::kScanModeCount).answer, AnswerType::kLidarConf);
  EXPECT_EQ(encode_get_acc_board_flag().answer, AnswerType::kAccBoardFlag);
  EXPECT_EQ(encode_express_scan(3, AnswerType::kUltraCapsule).answer, AnswerType::kUltraCapsule);
  EXPECT_FALSE(encode_set_motor_pwm(0).answer.has_value());
}

TEST(RplidarRequest, ExpressScanCarriesMode) {
  const V b = bytes(encode_express_scan(2, AnswerType::kUltraCapsule));
  ASSERT_EQ(b.size(), 9U);
  EXPECT_EQ(b[3], 2);
  EXPECT_EQ(b[8], 0xA5 ^ 0x82 ^ 0x05 ^ 0x02);
}

TEST(RplidarRequest, PerModeConfCarriesModeId) {
  // GET_LIDAR_CONF(SCAN_MODE_ANS_TYPE = 0x75, mode 3): u32 type + u16 mode.
  const V b = bytes(encode_get_lidar_conf(ConfType::kScanModeAnsType, 3));
  EXPECT_EQ(b, (V{0xA5, 0x84, 0x06, 0x75, 0, 0, 0, 0x03, 0x00,
                  static_cast<std::uint8_t>(0xA5 ^ 0x84 ^ 0x06 ^ 0x75 ^ 0x03)}));
}

TEST(RplidarRequest, PwmIsClampedAndChecksumHolds) {
  const V b = bytes(encode_set_motor_pwm(5000));
  ASSERT_EQ(b.size(), 6U);
  EXPECT_EQ(b[3] | (b[4] << 8), kMaxMotorPwm);
  std::uint8_t x = 0;
  for (std::size_t i = 0; i + 1 < b.size(); ++i) x ^= b[i];
  EXPECT_EQ(x, b.back());
}

TEST(RplidarRequest, GenericEncoderRejectsMalformed) {
  const std::array<std::uint8_t, 1> one{1};
  EXPECT_FALSE(encode_request(0x25, one).has_value());  // short command with payload
  const std::array<std::uint8_t, 13> big{};
  EXPECT_FALSE(encode_request(0x84, big).has_value());
  const auto empty_long = encode_request(0x84, {});
  ASSERT_TRUE(empty_long.has_value());
  EXPECT_EQ(bytes(*empty_long), (V{0xA5, 0x84, 0x00, 0xA5 ^ 0x84}));
}

}  // namespace
}  // namespace coxswain::drivers::rplidar
