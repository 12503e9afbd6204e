// SPDX-License-Identifier: Apache-2.0
// Configuration encoders against the worked frames of docs/protocols.md 3.6/3.7, and the plan.
#include "coxswain/drivers/ublox/config.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "ublox_test_util.hpp"

namespace coxswain::drivers::ublox {
namespace {

using test::from_hex;

std::vector<std::uint8_t> vec(const UbxFrame& f) { return {f.bytes().begin(), f.bytes().end()}; }

TEST(UbloxConfig, F9MeasRateMatchesWorkedExample) {
  EXPECT_EQ(vec(f9_set_meas_period(100)),
            from_hex("B5 62 06 8A 0A 00 00 01 00 00 01 00 21 30 64 00 51 B9"));
}

TEST(UbloxConfig, F9NavPvtUsbMatchesWorkedExample) {
  EXPECT_EQ(vec(f9_set_nav_pvt_output(Port::kUsb, 1)),
            from_hex("B5 62 06 8A 09 00 00 01 00 00 09 00 91 20 01 55 52"));
  const auto uart = vec(f9_set_nav_pvt_output(Port::kUart1, 1));
  ASSERT_EQ(uart.size(), 17U);
  EXPECT_EQ(uart[10], 0x07);  // key 0x20910007 little-endian
  EXPECT_EQ(uart[13], 0x20);
}

TEST(UbloxConfig, M8CfgMsgMatchesWorkedExample) {
  EXPECT_EQ(vec(m8_set_msg_rate(kNavPvt, 1)), from_hex("B5 62 06 01 03 00 01 07 01 13 51"));
}

TEST(UbloxConfig, M8CfgRateMatchesWorkedExample) {
  EXPECT_EQ(vec(m8_set_rate(200, 1)), from_hex("B5 62 06 08 06 00 C8 00 01 00 01 00 DE 6A"));
}

TEST(UbloxConfig, DynModelFrames) {
  const auto f9 = vec(f9_set_dyn_model(kDynModelSea));
  EXPECT_EQ(std::vector<std::uint8_t>(f9.begin() + 6, f9.end() - 2),
            from_hex("00 01 00 00 21 00 11 20 05"));
  const UbxFrame m8 = m8_set_dyn_model(kDynModelSea);
  ASSERT_EQ(m8.size, 44U);
  EXPECT_EQ(m8.id(), kCfgNav5);
  EXPECT_EQ(m8.data[6], 0x01);  // mask: dynModel only
  EXPECT_EQ(m8.data[7], 0x00);
  EXPECT_EQ(m8.data[8], 5);
  // The decoder accepts every frame we build (checksum and framing).
  Decoder d;
  const auto out = test::decode_all(d, m8.bytes());
  ASSERT_EQ(out.size(), 1U);
  EXPECT_EQ(out[0].ubx, kCfgNav5);
}

TEST(UbloxConfig, ValsetKeySizesAndRangeChecks) {
  EXPECT_EQ(valset_value_size(key::kRateMeas), 2U);
  EXPECT_EQ(valset_value_size(key::kNavspgDynModel), 1U);
  EXPECT_EQ(valset_value_size(key::kUsbOutProtNmea), 1U);
  EXPECT_EQ(valset_value_size(0x40520001), 4U);
  EXPECT_EQ(valset_value_size(0x50000001), 8U);
  EXPECT_EQ(valset_value_size(0x00000001), 0U);
  ValsetBuilder b;
  EXPECT_FALSE(b.add(key::kUsbOutProtNmea, 2));    // a bit key holds 0/1
  EXPECT_FALSE(b.add(key::kNavspgDynModel, 256));  // U1
  EXPECT_FALSE(b.add(key::kRateMeas, 70000));      // U2
  EXPECT_FALSE(b.add(0x00000001, 1));              // no size
  EXPECT_TRUE(b.add(key::kRateMeas, 100));
  EXPECT_EQ(vec(b.build()), from_hex("B5 62 06 8A 0A 00 00 01 00 00 01 00 21 30 64 00 51 B9"));
  ValsetBuilder full;
  int added = 0;
  while (full.add(key::kNavspgDynModel, 5)) ++added;
  EXPECT_EQ(added, (256 - 8 - 4) / 5);
  EXPECT_EQ(full.build().size, 8U + 4U + static_cast<std::size_t>(added) * 5U);
}

TEST(UbloxConfig, OversizedPayloadGivesEmptyFrame) {
  const std::vector<std::uint8_t> big(kMaxConfigFrameBytes, 0);
  EXPECT_EQ(make_ubx_frame(kCfgValset, big).size, 0U);
}

TEST(UbloxConfig, ParamsValidation) {
  ConfigParams p;
  EXPECT_FALSE(p.validate(Generation::kM8));
  EXPECT_FALSE(p.validate(Generation::kF9));
  p.rate_hz = 15.0;
  EXPECT_TRUE(p.validate(Generation::kM8));
  EXPECT_FALSE(p.validate(Generation::kF9));
  p.rate_hz = 0.0;
  EXPECT_TRUE(p.validate(Generation::kF9));
  p.rate_hz = std::nan("");
  EXPECT_TRUE(p.validate(Generation::kF9));
  EXPECT_EQ(make_config_plan(Generation::kF9, p).count, 0U);
  p.rate_hz = 3.0;
  EXPECT_EQ(p.meas_period_ms(), 333);
}

TEST(UbloxConfig, F9PlanOrderAndAcks) {
  ConfigParams p;
  p.rate_hz = 10.0;
  p.port = Port::kUsb;
  p.nmea_enabled = false;
  const ConfigPlan plan = make_config_plan(Generation::kF9, p);
  ASSERT_EQ(plan.count, 4U);
  for (const ConfigStep& s : plan.view()) {
    EXPECT_EQ(s.ack_for, kCfgValset);
    EXPECT_GT(s.frame.size, 8U);
    EXPECT_FALSE(s.what.empty());
  }
  EXPECT_EQ(vec(plan.steps[0].frame),
            from_hex("B5 62 06 8A 0A 00 00 01 00 00 01 00 21 30 64 00 51 B9"));
  EXPECT_EQ(vec(plan.steps[3].frame),
            from_hex("B5 62 06 8A 09 00 00 01 00 00 09 00 91 20 01 55 52"));
  // Output protocols on USB: UBX on, NMEA off (two L keys).
  EXPECT_EQ(std::vector<std::uint8_t>(plan.steps[2].frame.data.begin() + 6,
                                      plan.steps[2].frame.data.begin() + 20),
            from_hex("00 01 00 00 01 00 78 10 01 02 00 78 10 00"));
  p.port = Port::kUart1;
  p.nmea_enabled = true;
  const ConfigPlan uart = make_config_plan(Generation::kF9, p);
  ASSERT_EQ(uart.count, 4U);
  EXPECT_EQ(uart.steps[2].frame.size, 8U + 4U + 4U * 5U);  // UBX, NMEA, GGA, RMC
  EXPECT_EQ(uart.steps[3].frame.data[10], 0x07);           // NAV-PVT on UART1
}

TEST(UbloxConfig, M8PlanOrderAndAcks) {
  ConfigParams p;
  p.rate_hz = 5.0;
  p.nmea_enabled = false;
  const ConfigPlan plan = make_config_plan(Generation::kM8, p);
  ASSERT_EQ(plan.count, 9U);
  EXPECT_EQ(vec(plan.steps[0].frame), from_hex("B5 62 06 08 06 00 C8 00 01 00 01 00 DE 6A"));
  EXPECT_EQ(plan.steps[0].ack_for, kCfgRate);
  EXPECT_EQ(plan.steps[1].ack_for, kCfgNav5);
  EXPECT_EQ(vec(plan.steps[2].frame), from_hex("B5 62 06 01 03 00 01 07 01 13 51"));
  for (std::size_t i = 2; i < plan.count; ++i) EXPECT_EQ(plan.steps[i].ack_for, kCfgMsg);
  for (std::size_t i = 3; i < plan.count; ++i) {
    EXPECT_EQ(plan.steps[i].frame.data[6], 0xF0);  // NMEA class
    EXPECT_EQ(plan.steps[i].frame.data[8], 0);     // rate 0 = off
  }
  p.nmea_enabled = true;
  const ConfigPlan on = make_config_plan(Generation::kM8, p);
  ASSERT_EQ(on.count, 5U);
  EXPECT_EQ(on.steps[3].frame.data[7], 0x00);  // GGA
  EXPECT_EQ(on.steps[4].frame.data[7], 0x04);  // RMC
  EXPECT_EQ(on.steps[4].frame.data[8], 1);
  // Every planned frame is a valid UBX frame for our own decoder.
  Decoder d;
  std::vector<std::uint8_t> all;
  for (const ConfigStep& s : on.view()) test::append(all, s.frame.bytes());
  const auto out = test::decode_all(d, all);
  ASSERT_EQ(out.size(), on.count);
  EXPECT_EQ(d.stats().checksum_errors, 0U);
}

}  // namespace
}  // namespace coxswain::drivers::ublox
