// SPDX-License-Identifier: Apache-2.0
// The RPLIDAR emulator (tools/sim/devices/rplidar) checked through the production decoder: the
// answers, the standard/express/dense streams (angles and distances must decode to the ranges it
// was given), the motor rules, health injection, faults, and the recorded-scan source.
#include "sim/devices/rplidar/emulator.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "coxswain/drivers/rplidar/codec.hpp"
#include "coxswain/drivers/rplidar/request.hpp"
#include "support/testdata.hpp"

namespace coxswain::sim::devices::rplidar {
namespace {

namespace d = drivers::rplidar;
constexpr core::TimeNs kMs = core::kNsPerMs;

struct Decoded {
  std::vector<d::Message> answers;
  std::vector<d::HqNode> nodes;
};

void feed(d::Decoder& dec, std::span<const std::uint8_t> bytes, Decoded& out) {
  while (!bytes.empty()) {
    const auto step = dec.decode(bytes);
    bytes = bytes.subspan(step.consumed);
    if (!step.produced) continue;
    if (dec.message().kind == d::MessageKind::kNodes) {
      for (const auto& n : dec.message().nodes.span()) out.nodes.push_back(n);
    } else {
      out.answers.push_back(dec.message());
    }
  }
}

/// Sends `r`, tells the decoder what to expect, and collects everything up to `until`.
Decoded exchange(Emulator& e, d::Decoder& dec, const d::Request& r, core::TimeNs at,
                 core::TimeNs until) {
  if (r.answer) dec.expect(*r.answer);
  e.receive(r.span(), at);
  Decoded out;
  for (core::TimeNs t = at; t <= until; t += 10 * kMs) feed(dec, e.poll(t), out);
  return out;
}

std::vector<float> ramp_ranges() {
  std::vector<float> r(720);
  for (std::size_t i = 0; i < r.size(); ++i) r[i] = 1.0F + 0.01F * static_cast<float>(i / 2);
  return r;
}

float expected_at(const std::vector<float>& r, double angle_deg) {
  const auto n = static_cast<long long>(r.size());
  return r[static_cast<std::size_t>(std::llround(angle_deg / 360.0 * static_cast<double>(n)) % n)];
}

/// The decoded angle is quantised (standard: 1/64 deg; capsules: interpolated and truncated), so a
/// sample at a beam edge may have been taken from the neighbouring beam: accept either.
::testing::AssertionResult matches_beam(const std::vector<float>& r, double angle_deg, float got_m,
                                        float tolerance_m) {
  const auto n = static_cast<long long>(r.size());
  const long long k = std::llround(angle_deg / 360.0 * static_cast<double>(n));
  for (long long dk = -1; dk <= 1; ++dk) {
    const float want = r[static_cast<std::size_t>(((k + dk) % n + n) % n)];
    if (std::fabs(want - got_m) <= tolerance_m) return ::testing::AssertionSuccess();
  }
  return ::testing::AssertionFailure() << "at " << angle_deg << " deg got " << got_m << " m, beam "
                                       << k << " holds " << expected_at(r, angle_deg);
}

TEST(RplidarEmulator, AnswersInfoHealthSampleRateAndConf) {
  Emulator e(EmulatorConfig{Model::kS2});
  d::Decoder dec;
  auto got = exchange(e, dec, d::encode_get_info(), 0, 0);
  ASSERT_EQ(got.answers.size(), 1U);
  EXPECT_EQ(got.answers[0].device_info, e.profile().info);
  EXPECT_EQ(d::model_info(got.answers[0].device_info).family, d::Family::kS);
  got = exchange(e, dec, d::encode_get_health(), 0, 0);
  ASSERT_EQ(got.answers.size(), 1U);
  EXPECT_EQ(got.answers[0].health, (d::Health{0, 0}));
  got = exchange(e, dec, d::encode_get_sample_rate(), 0, 0);
  ASSERT_EQ(got.answers.size(), 1U);
  EXPECT_EQ(got.answers[0].sample_rate.express_us, 31);
  got = exchange(e, dec, d::encode_get_lidar_conf(d::ConfType::kScanModeTypical), 0, 0);
  ASSERT_EQ(got.answers.size(), 1U);
  EXPECT_EQ(got.answers[0].lidar_conf.as_uint(2), 1U);
  got = exchange(e, dec, d::encode_get_lidar_conf(d::ConfType::kScanModeAnsType, 1), 0, 0);
  ASSERT_EQ(got.answers.size(), 1U);
  EXPECT_EQ(got.answers[0].lidar_conf.as_uint(1), 0x85U);
  got = exchange(e, dec, d::encode_get_lidar_conf(d::ConfType::kScanModeUsPerSample, 1), 0, 0);
  EXPECT_EQ(got.answers.at(0).lidar_conf.as_uint(4), 8000U);  // 31.25 us in q8
  got = exchange(e, dec, d::encode_get_lidar_conf(d::ConfType::kScanModeName, 1), 0, 0);
  EXPECT_EQ(got.answers.at(0).lidar_conf.as_text(), "DenseBoost");
  EXPECT_EQ(e.stats().bad_requests, 0U);
}

TEST(RplidarEmulator, OldFirmwareIgnoresConfAndBadChecksumsGetNoAnswer) {
  Emulator e(EmulatorConfig{Model::kA2});  // firmware 1.20
  d::Decoder dec;
  auto got = exchange(e, dec, d::encode_get_lidar_conf(d::ConfType::kScanModeTypical), 0, 0);
  EXPECT_TRUE(got.answers.empty());
  d::Request bad = d::encode_express_scan(0);
  bad.bytes[bad.size - 1] ^= 0xFF;
  got = exchange(e, dec, bad, 0, 500 * kMs);
  EXPECT_TRUE(got.answers.empty());
  EXPECT_TRUE(got.nodes.empty());
  EXPECT_EQ(e.stats().bad_requests, 1U);
  got = exchange(e, dec, d::encode_get_acc_board_flag(), 0, 0);
  ASSERT_EQ(got.answers.size(), 1U);
  EXPECT_TRUE(got.answers[0].acc_board.pwm_supported());
}

struct StreamCase {
  Model model;
  bool express;
  double us;
};

class Streams : public ::testing::TestWithParam<StreamCase> {};

TEST_P(Streams, DecodeToTheGivenRangesAtTheRevolutionRate) {
  const StreamCase c = GetParam();
  EmulatorConfig cfg{c.model};
  cfg.spin_up_ms = 0;
  Emulator e(cfg);
  const auto ranges = ramp_ranges();
  e.set_ranges(ranges);
  d::Decoder dec;
  if (c.model == Model::kA2) (void)exchange(e, dec, d::encode_set_motor_pwm(660), 0, 0);
  const d::Request r =
      c.express ? d::encode_express_scan(1, e.profile().modes[1].answer) : d::encode_scan();
  const Decoded got = exchange(e, dec, r, 0, 1'000 * kMs);
  // One second at 10 Hz: 1e6 / us samples (the last partial capsule and the decoder's one-capsule
  // delay aside).
  EXPECT_NEAR(static_cast<double>(got.nodes.size()), 1e6 / c.us, 100.0);
  int starts = 0;
  for (const d::HqNode& n : got.nodes) {
    starts += n.start_of_scan() ? 1 : 0;
    EXPECT_TRUE(
        matches_beam(ranges, n.angle_deg(), static_cast<float>(n.distance_mm() / 1000.0), 0.0011F));
  }
  EXPECT_NEAR(starts, 10, 1);
  EXPECT_EQ(dec.stats().codec.checksum_errors, 0U);
  EXPECT_EQ(dec.stats().codec.framing_errors, 0U);
}

INSTANTIATE_TEST_SUITE_P(
    Models, Streams,
    ::testing::Values(StreamCase{Model::kA1, false, 500.0}, StreamCase{Model::kA1, true, 250.0},
                      StreamCase{Model::kA2, true, 250.0}, StreamCase{Model::kS1, true, 108.0},
                      StreamCase{Model::kC1, false, 200.0}, StreamCase{Model::kS2, true, 31.25}));

TEST(RplidarEmulator, MotorRulesPerModel) {
  {
    Emulator a1(EmulatorConfig{Model::kA1});
    a1.set_dtr(true);  // as after open on Linux
    d::Decoder dec;
    auto got = exchange(a1, dec, d::encode_scan(), 0, 1'000 * kMs);
    EXPECT_TRUE(got.nodes.empty()) << "A1 motor stopped while DTR is asserted";
    a1.set_dtr(false);
    got = exchange(a1, dec, d::Request{}, 1'010 * kMs, 1'300 * kMs);
    EXPECT_TRUE(got.nodes.empty()) << "spinning up (300 ms)";
    got = exchange(a1, dec, d::Request{}, 1'310 * kMs, 2'000 * kMs);
    EXPECT_FALSE(got.nodes.empty());
  }
  {
    Emulator a3(EmulatorConfig{Model::kA3});
    d::Decoder dec;
    auto got = exchange(a3, dec, d::encode_express_scan(1), 0, 1'000 * kMs);
    EXPECT_TRUE(got.nodes.empty()) << "A3 without PWM does not spin";
    (void)exchange(a3, dec, d::encode_set_motor_pwm(600), 1'000 * kMs, 1'000 * kMs);
    dec.expect(d::AnswerType::kCapsule);
    got = exchange(a3, dec, d::encode_express_scan(1), 1'000 * kMs, 2'000 * kMs);
    EXPECT_FALSE(got.nodes.empty());
    EXPECT_EQ(a3.stats().motor_pwm, 600);
  }
  {
    Emulator s1(EmulatorConfig{Model::kS1});
    d::Decoder dec;
    (void)exchange(s1, dec, d::encode_hq_motor_speed(300), 0, 0);
    EXPECT_DOUBLE_EQ(s1.revolution_hz(), 5.0);
  }
}

TEST(RplidarEmulator, HealthErrorRefusesScansUntilReset) {
  EmulatorConfig cfg{Model::kA2};
  cfg.health_status = 2;
  cfg.health_error_code = 0x8001;
  Emulator e(cfg);
  d::Decoder dec;
  auto got = exchange(e, dec, d::encode_get_health(), 0, 0);
  EXPECT_EQ(got.answers.at(0).health, (d::Health{2, 0x8001}));
  got = exchange(e, dec, d::encode_scan(), 0, 100 * kMs);
  EXPECT_TRUE(got.answers.empty());
  EXPECT_FALSE(e.scanning());
  (void)exchange(e, dec, d::encode_reset(), 200 * kMs, 200 * kMs);
  got = exchange(e, dec, d::encode_get_health(), 300 * kMs, 300 * kMs);
  EXPECT_TRUE(got.answers.empty()) << "rebooting: requests are lost";
  dec.reset();
  // The A2 prints its banner after the reboot; the decoder skips it.
  got = exchange(e, dec, d::encode_get_health(), 800 * kMs, 800 * kMs);
  ASSERT_EQ(got.answers.size(), 1U);
  EXPECT_EQ(got.answers[0].health, (d::Health{0, 0}));
  EXPECT_GT(dec.stats().codec.bytes_skipped, 40U) << "banner";
}

TEST(RplidarEmulator, CorruptedCapsulesFailTheirChecksumAndGarbageIsSkipped) {
  EmulatorConfig cfg{Model::kA1};
  cfg.spin_up_ms = 0;
  cfg.faults.corrupt_probability = 0.05;
  cfg.faults.garbage_probability = 0.05;
  cfg.faults.seed = 99;
  Emulator e(cfg);
  e.set_ranges(ramp_ranges());
  d::Decoder dec;
  (void)exchange(e, dec, d::encode_express_scan(0), 0, 3'000 * kMs);
  EXPECT_GT(e.stats().corrupted_frames, 10U);
  EXPECT_GT(e.stats().garbage_bursts, 10U);
  EXPECT_GE(dec.stats().codec.checksum_errors, e.stats().corrupted_frames / 2);
  EXPECT_GT(dec.stats().codec.frames_ok, e.stats().data_frames / 2);
}

TEST(RplidarEmulator, SilentSendsNothingAndStopEndsTheStream) {
  EmulatorConfig cfg{Model::kC1};
  cfg.spin_up_ms = 0;
  cfg.faults.silent = true;
  Emulator e(cfg);
  d::Decoder dec;
  auto got = exchange(e, dec, d::encode_get_info(), 0, 500 * kMs);
  EXPECT_TRUE(got.answers.empty());
  e.set_faults({});
  got = exchange(e, dec, d::encode_scan(), 500 * kMs, 700 * kMs);
  EXPECT_FALSE(got.nodes.empty());
  (void)exchange(e, dec, d::encode_stop(), 710 * kMs, 710 * kMs);
  EXPECT_FALSE(e.scanning());
  got = exchange(e, dec, d::Request{}, 720 * kMs, 900 * kMs);
  EXPECT_TRUE(got.nodes.empty());
}

TEST(RplidarEmulator, RangeSourceIsAskedEveryRevolution) {
  EmulatorConfig cfg{Model::kA1};
  cfg.spin_up_ms = 0;
  Emulator e(cfg);
  std::vector<std::uint64_t> asked;
  e.set_range_source(360, [&](std::uint64_t rev, std::span<float> r) {
    asked.push_back(rev);
    std::fill(r.begin(), r.end(), 1.0F + static_cast<float>(rev));
  });
  d::Decoder dec;
  const Decoded got = exchange(e, dec, d::encode_scan(), 0, 500 * kMs);
  EXPECT_GE(asked.size(), 5U);
  ASSERT_FALSE(got.nodes.empty());
  EXPECT_NEAR(got.nodes.front().distance_mm(), 1000.0, 1.0);
  EXPECT_GT(got.nodes.back().distance_mm(), 4000.0);
}

TEST(RplidarEmulator, RecordedScansPlayBackInTheLidarsOwnAngles) {
  COXSWAIN_REQUIRE_TESTDATA(path, "peer/tricat221-0223-scans.jsonl");
  std::string error;
  const auto rec = RecordedScans::load(path, &error);
  ASSERT_TRUE(rec.has_value()) << error;
  EXPECT_EQ(rec->size(), 174U);
  EXPECT_EQ(rec->beams(), 1360U);
  // The boat's own hull is close behind the lidar on the source boat: most beams have returns.
  std::size_t returns = 0;
  for (const float r : rec->scan(0)) returns += r > 0.0F ? 1 : 0;
  EXPECT_GT(returns, 600U);
  EmulatorConfig cfg{Model::kA3};
  cfg.spin_up_ms = 0;
  Emulator e(cfg);
  e.set_range_source(rec->beams(), rec->source());
  d::Decoder dec;
  (void)exchange(e, dec, d::encode_set_motor_pwm(660), 0, 0);
  const Decoded got = exchange(e, dec, d::encode_express_scan(1), 0, 95 * kMs);
  ASSERT_GT(got.nodes.size(), 300U);
  const auto scan0 = rec->scan(0);
  std::vector<float> first(scan0.begin(), scan0.end());
  int compared = 0;
  for (const d::HqNode& n : got.nodes) {
    if (expected_at(first, n.angle_deg()) > 25.0F) continue;  // beyond the A3's range
    EXPECT_TRUE(
        matches_beam(first, n.angle_deg(), static_cast<float>(n.distance_mm() / 1000.0), 0.0011F));
    ++compared;
  }
  EXPECT_GT(compared, 300);
}

}  // namespace
}  // namespace coxswain::sim::devices::rplidar
