// SPDX-License-Identifier: Apache-2.0
// ScanAssembler: seam astern, body-frame bearings, and a full round trip of real peer scans
// encoded as standard nodes -> Decoder -> ScanAssembler.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "coxswain/core/angles.hpp"
#include "coxswain/drivers/rplidar/answer_encoder.hpp"
#include "coxswain/drivers/rplidar/codec.hpp"
#include "coxswain/drivers/rplidar/scan_assembler.hpp"
#include "decode_helpers.hpp"
#include "support/testdata.hpp"

namespace coxswain::drivers::rplidar {
namespace {

HqNode node_at(double lidar_deg, double range_m, bool start) {
  HqNode n;
  const auto q6 =
      static_cast<std::uint16_t>(std::lround(core::wrap_deg_360(lidar_deg) * 64.0) % 23040);
  n.angle_z_q14 = static_cast<std::uint16_t>((q6 * 256U) / 90U);
  n.dist_mm_q2 = static_cast<std::uint32_t>(std::lround(range_m * 4000.0));
  n.quality = 188;
  n.flag = start ? 1 : 2;
  return n;
}

struct SeamCase {
  double yaw_deg;
  bool clockwise;
};

// Feeds 3.5 lidar revolutions (lidar start flag at lidar 0 deg) and checks every emitted scan is
// cut at the body stern: the first sample in time lies just past 180, the last just before it.
TEST(RplidarScanAssembler, SeamIsAsternWhateverTheMount) {
  for (const SeamCase c : {SeamCase{180.0, true}, SeamCase{0.0, true}, SeamCase{90.0, true},
                           SeamCase{180.0, false}, SeamCase{-37.0, false}}) {
    SCOPED_TRACE(::testing::Message() << "yaw " << c.yaw_deg << " cw " << c.clockwise);
    ScanAssemblerParams p;
    p.mount.yaw_deg = c.yaw_deg;
    p.clockwise = c.clockwise;
    p.max_range_m = 40.0F;
    p.sample_duration_us = 250.0;
    ASSERT_FALSE(p.validate().has_value());
    auto a = std::make_unique<ScanAssembler>(p);
    int emitted = 0;
    const int per_rev = 720;
    for (int i = 0; i < per_rev * 7 / 2; ++i) {
      const double lidar_deg = 0.25 + 0.5 * (i % per_rev);  // never exactly on the seam
      if (!a->add(node_at(lidar_deg, 5.0, i % per_rev == 0), i * 250'000LL)) continue;
      ++emitted;
      const msg::LidarScan& s = a->scan();
      ASSERT_EQ(s.point_count, static_cast<std::uint32_t>(per_rev));
      for (std::uint32_t k = 1; k < s.point_count; ++k) {
        ASSERT_LE(s.points[k - 1].bearing_deg, s.points[k].bearing_deg);
      }
      // Sorted by bearing: the port-side stern comes first. A clockwise lidar sweeps it first
      // in time, a counter-clockwise one last.
      EXPECT_LT(s.points.front().bearing_deg, -179.0F);
      EXPECT_GT(s.points[s.point_count - 1].bearing_deg, 179.0F);
      const std::int32_t last_us = (per_rev - 1) * 250;
      EXPECT_EQ(s.points.front().offset_us, c.clockwise ? 0 : last_us);
      EXPECT_EQ(s.points[s.point_count - 1].offset_us, c.clockwise ? last_us : 0);
      EXPECT_EQ(s.duration_ns, (per_rev - 1) * 250'000LL);
      // The bow (bearing 0) sits mid-revolution in time, never at a seam.
      for (std::uint32_t k = 0; k < s.point_count; ++k) {
        if (std::fabs(s.points[k].bearing_deg) < 0.01F) {
          EXPECT_NEAR(s.points[k].offset_us, per_rev / 2 * 250, 250);
        }
      }
    }
    // The first partial revolution is dropped and the last is still open.
    EXPECT_GE(emitted, 2);
    EXPECT_LE(emitted, 3);
  }
}

TEST(RplidarScanAssembler, MountYaw180TurnsLidarZeroToStern) {
  ScanAssemblerParams p;
  p.mount.yaw_deg = 180.0;
  ScanAssembler a(p);
  EXPECT_NEAR(a.body_bearing_deg(0.0), 180.0, 1e-9);
  EXPECT_NEAR(a.body_bearing_deg(90.0), -90.0, 1e-9);
  p.clockwise = false;
  ScanAssembler b(p);
  EXPECT_NEAR(b.body_bearing_deg(90.0), 90.0, 1e-9);
}

TEST(RplidarScanAssembler, JitterAtTheSeamCutsOnce) {
  ScanAssemblerParams p;  // yaw 0: seam at lidar 180
  p.max_range_m = 40.0F;
  ScanAssembler a(p);
  int emitted = 0;
  const std::vector<double> angles = {170, 175, 179.5, 180.3, 179.8, 181,   185,   300,
                                      10,  100, 170,   179.7, 180.2, 179.9, 180.5, 200};
  for (std::size_t round = 0; round < 3; ++round) {
    for (const double deg : angles) {
      if (!a.add(node_at(deg, 3.0, false), 0)) continue;
      ++emitted;
      // A double cut would emit a scan of one or two jittering samples.
      EXPECT_GE(a.scan().point_count, angles.size() / 2);
    }
  }
  EXPECT_GE(emitted, 2);
}

TEST(RplidarScanAssembler, RangeLimits) {
  ScanAssemblerParams p;
  p.min_range_m = 0.2F;
  p.max_range_m = 10.0F;
  ScanAssembler a(p);
  bool emitted = false;
  for (int rev = 0; rev < 3 && !emitted; ++rev) {
    for (int i = 0; i < 360; ++i) {
      const double r = i == 10 ? 0.1 : (i == 20 ? 11.0 : (i == 30 ? 0.0 : 4.0));
      if (a.add(node_at(i, r, i == 0), 0) && rev == 2) emitted = true;
    }
  }
  ASSERT_GE(a.revolutions(), 1U);
  const auto& s = a.scan();
  int zeros = 0;
  for (std::uint32_t k = 0; k < s.point_count; ++k) zeros += s.points[k].range_m == 0.0F ? 1 : 0;
  EXPECT_EQ(zeros, 3);
  EXPECT_EQ(s.point_count, 360U);
}

// Real scans of the 2022 boat: ROS angles theta_ros = pi - theta_raw. Each scan is encoded as
// standard nodes in lidar order, decoded, assembled with the lidar mounted astern (yaw 180), and
// must come back as the original beams at body bearing -theta_ros within quantisation.
TEST(RplidarScanAssembler, PeerScansRoundTripThroughStandardNodes) {
  COXSWAIN_REQUIRE_TESTDATA(path, "peer/tricat221-0223-scans.jsonl");
  std::ifstream in(path);
  std::string line;
  struct Beam {
    double bearing_deg;
    double range_m;
  };
  std::vector<std::vector<Beam>> originals;
  std::vector<std::uint8_t> stream;
  test::append(stream, encode_descriptor(AnswerType::kMeasurement));
  while (std::getline(in, line) && originals.size() < 20) {
    const auto j = nlohmann::json::parse(line);
    if (j["topic"] != "scan") continue;
    const double amin = j["angle_min"].get<double>();
    const double inc = j["angle_increment"].get<double>();
    const auto& ranges = j["ranges"];
    std::vector<Beam> beams;
    // Lidar order: raw angle ascending = theta_ros descending.
    // Beams 0 and n-1 (theta -pi and +pi) point the same way; the lidar measures it once.
    for (std::size_t k = ranges.size(); k-- > 1;) {
      const double theta_ros = amin + inc * static_cast<double>(k);
      const double raw_deg = core::wrap_deg_360(core::rad_to_deg(core::kPi - theta_ros));
      const double r = ranges[k].is_null() ? 0.0 : ranges[k].get<double>();
      const auto q6 = static_cast<std::uint16_t>(std::lround(raw_deg * 64.0) % 23040);
      const auto q2 = static_cast<std::uint16_t>(std::lround(r * 4000.0));
      test::append(stream, encode_standard_node(k + 1 == ranges.size(), r > 0 ? 47 : 0, q6, q2));
      beams.push_back({core::wrap_deg(q6 / 64.0 + 180.0), q2 / 4000.0});
    }
    originals.push_back(beams);
  }
  ASSERT_EQ(originals.size(), 20U);

  Decoder d;
  d.expect(AnswerType::kMeasurement);
  ScanAssemblerParams p;
  p.mount.yaw_deg = 180.0;
  p.min_range_m = 0.0F;
  p.max_range_m = 40.0F;
  auto a = std::make_unique<ScanAssembler>(p);
  std::vector<std::vector<msg::LidarPoint>> scans;
  std::span<const std::uint8_t> rest = stream;
  while (!rest.empty()) {
    const DecodeStep step = d.decode(rest);
    rest = rest.subspan(step.consumed);
    if (!step.produced) continue;
    for (const HqNode& n : d.message().nodes.span()) {
      if (a->add(n, 0)) {
        const auto& s = a->scan();
        scans.emplace_back(s.points.begin(), s.points.begin() + s.point_count);
      }
    }
  }
  EXPECT_EQ(d.stats().codec.framing_errors, 0U);
  // The seam is at body 180 = lidar 0, so revolution n is peer scan n (the first may be partial).
  ASSERT_GE(scans.size(), 15U);
  std::size_t compared = 0;
  for (std::size_t n = 0; n < scans.size(); ++n) {
    // Find the original this revolution equals (scans follow in order, after the first one).
    auto want = originals[n + 1];
    std::sort(want.begin(), want.end(),
              [](const Beam& x, const Beam& y) { return x.bearing_deg < y.bearing_deg; });
    ASSERT_EQ(scans[n].size(), want.size()) << n;
    for (std::size_t k = 0; k < want.size(); ++k) {
      EXPECT_NEAR(scans[n][k].bearing_deg, want[k].bearing_deg, 0.03) << n << "," << k;
      EXPECT_NEAR(scans[n][k].range_m, want[k].range_m, 1e-6) << n << "," << k;
      ++compared;
    }
  }
  EXPECT_GT(compared, 15U * 1000U);
}

}  // namespace
}  // namespace coxswain::drivers::rplidar
