// SPDX-License-Identifier: Apache-2.0
#include "sim/sensors/lidar_sim.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "coxswain/core/angles.hpp"
#include "coxswain/drivers/rplidar/scan_assembler.hpp"

namespace coxswain::sim::sensors {
namespace {

LidarSimConfig quiet_config() {
  LidarSimConfig c = LidarSimConfig::for_model(LidarModel::kA2M8);
  c.range_sigma_m = 0.0;
  c.range_sigma_fraction = 0.0;
  c.dropout_probability = 0.0;
  c.spurious_probability = 0.0;
  return c;
}

/// A room around the origin: walls 5 m north, 4 m south, 3 m east, 6 m west.
RayScene room() {
  RayScene s;
  s.add_segment({{5.0, -6.0}, {5.0, 3.0}});
  s.add_segment({{5.0, 3.0}, {-4.0, 3.0}});
  s.add_segment({{-4.0, 3.0}, {-4.0, -6.0}});
  s.add_segment({{-4.0, -6.0}, {5.0, -6.0}});
  return s;
}

const msg::LidarPoint* nearest_bearing(const msg::LidarScan& scan, double bearing_deg) {
  const msg::LidarPoint* best = nullptr;
  double best_err = 1e9;
  for (std::uint32_t i = 0; i < scan.point_count; ++i) {
    const double e =
        std::abs(core::wrap_deg(static_cast<double>(scan.points[i].bearing_deg) - bearing_deg));
    if (e < best_err) {
      best_err = e;
      best = &scan.points[i];
    }
  }
  return best;
}

TEST(LidarSim, ModelFigures) {
  const LidarSimConfig a2 = LidarSimConfig::for_model(LidarModel::kA2M8);
  EXPECT_EQ(a2.beams_per_revolution(), 800);
  EXPECT_NEAR(a2.sample_duration_us(), 125.0, 1e-9);  // 8 kSa/s
  EXPECT_EQ(LidarSimConfig::for_model(LidarModel::kS2).beams_per_revolution(), 3200);
  for (auto m :
       {LidarModel::kA1, LidarModel::kA2M8, LidarModel::kA3, LidarModel::kS2, LidarModel::kC1}) {
    EXPECT_FALSE(LidarSimConfig::for_model(m).validate().has_value());
  }
  LidarSimConfig bad = a2;
  bad.max_range_m = 0.1;
  EXPECT_TRUE(bad.validate().has_value());
}

TEST(LidarSim, StationaryRoomSternMountedLidarGivesBodyFrameRanges) {
  LidarSim sim(quiet_config(), room());
  BoatTruth truth;  // heading north at the origin
  bool got = false;
  for (core::TimeNs t = 0; t <= core::ms_to_ns(400) && !got; t += core::ms_to_ns(10)) {
    got = sim.update(t, truth).scan_ready;
  }
  ASSERT_TRUE(got);
  const msg::LidarScan& scan = sim.scan();
  ASSERT_EQ(scan.point_count, 800U);
  // Seam astern: bearings ascend from just above -180 to 180, first sample at offset 0.
  for (std::uint32_t i = 1; i < scan.point_count; ++i) {
    ASSERT_LE(scan.points[i - 1].bearing_deg, scan.points[i].bearing_deg);
  }
  EXPECT_GT(scan.points[0].bearing_deg, -180.0F);
  EXPECT_LT(scan.points[0].bearing_deg, -179.0F);
  // The first sample (offset 0) is the one that crossed the seam: it sorts to the +180 end.
  const msg::LidarPoint* first = nullptr;
  for (std::uint32_t i = 0; i < scan.point_count; ++i) {
    if (scan.points[i].offset_us == 0) first = &scan.points[i];
  }
  ASSERT_NE(first, nullptr);
  EXPECT_GE(std::abs(first->bearing_deg), 179.5F);
  EXPECT_NEAR(core::ns_to_sec(scan.duration_ns), 0.0999, 0.001);
  // The 2022 mount: lidar 0 deg faces the stern; the driver's frame puts the bow at bearing 0.
  EXPECT_NEAR(nearest_bearing(scan, 0.0)->range_m, 5.0, 0.001);
  EXPECT_NEAR(nearest_bearing(scan, 90.0)->range_m, 3.0, 0.001);
  EXPECT_NEAR(nearest_bearing(scan, -90.0)->range_m, 6.0, 0.001);
  EXPECT_NEAR(nearest_bearing(scan, 180.0)->range_m, 4.0, 0.001);
  // The raw revolution is in the lidar's own frame: its 0 deg looks astern (south wall, 4 m).
  ASSERT_EQ(sim.raw_revolution().size(), 800U);
  EXPECT_TRUE(sim.raw_revolution()[0].start_flag);
  EXPECT_NEAR(sim.raw_revolution()[0].range_m, 4.0, 0.001);
  EXPECT_NEAR(sim.raw_revolution()[200].angle_deg, 90.0, 1e-4);
  EXPECT_NEAR(sim.raw_revolution()[200].range_m, 6.0, 0.001);  // lidar 90 = port when astern
}

TEST(LidarSim, RawBeamsThroughTheDriversAssemblerGiveTheSameScan) {
  LidarSimConfig c = quiet_config();
  c.mount = {37.0, 0.2, -0.1};  // an odd mount so the seam is not at the lidar's own 0
  c.range_sigma_m = 0.02;
  c.dropout_probability = 0.05;
  c.spurious_probability = 0.01;
  LidarSim sim(c, room());
  drivers::rplidar::ScanAssemblerParams p;
  p.mount = c.mount;
  p.min_range_m = static_cast<float>(c.min_range_m);
  p.max_range_m = static_cast<float>(c.max_range_m);
  p.sample_duration_us = c.sample_duration_us();
  auto driver = std::make_unique<drivers::rplidar::ScanAssembler>(p);
  BoatTruth truth;
  truth.yaw_rate_dps = 30.0;
  int compared = 0;
  std::size_t fed = 0;
  for (core::TimeNs t = 0; t <= core::sec_to_ns(1.0); t += core::ms_to_ns(20)) {
    truth.pose.heading_deg = core::wrap_deg(30.0 * core::ns_to_sec(t));
    truth.pose.position.north_m = 0.3 * core::ns_to_sec(t);
    const LidarUpdate u = sim.update(t, truth);
    if (u.raw_ready) {
      for (const RawBeam& b : sim.raw_revolution()) {
        if (driver->add(b.to_hq(), b.stamp_ns)) {
          // The sim's assembler saw the same beams in the same order: identical scans.
          const msg::LidarScan& mine = driver->scan();
          const msg::LidarScan& sims = sim.scan();
          if (mine.revolution == sims.revolution) {
            ASSERT_EQ(mine.point_count, sims.point_count);
            EXPECT_EQ(mine.stamp_ns, sims.stamp_ns);
            EXPECT_EQ(mine.duration_ns, sims.duration_ns);
            for (std::uint32_t i = 0; i < mine.point_count; ++i) {
              ASSERT_EQ(mine.points[i].bearing_deg, sims.points[i].bearing_deg);
              ASSERT_EQ(mine.points[i].range_m, sims.points[i].range_m);
              ASSERT_EQ(mine.points[i].offset_us, sims.points[i].offset_us);
            }
            ++compared;
          }
        }
        ++fed;
      }
    }
  }
  EXPECT_GT(fed, 5000U);
  EXPECT_GE(compared, 5);
}

TEST(LidarSim, MotionSkewWhileTurning) {
  RayScene s;
  s.add_circle({{6.0, 0.0}, 0.3});  // a buoy due north
  LidarSim sim(quiet_config(), s);
  const double rate_dps = 180.0;
  BoatTruth truth;
  truth.yaw_rate_dps = rate_dps;
  int checked = 0;
  double max_naive_error = 0.0;
  for (core::TimeNs t = 0; t <= core::sec_to_ns(1.0); t += core::ms_to_ns(10)) {
    truth.pose.heading_deg = core::wrap_deg(rate_dps * core::ns_to_sec(t));
    if (!sim.update(t, truth).scan_ready) continue;
    const msg::LidarScan& scan = sim.scan();
    const double heading_at_stamp = rate_dps * core::ns_to_sec(scan.stamp_ns);
    for (std::uint32_t i = 0; i < scan.point_count; ++i) {
      const msg::LidarPoint& p = scan.points[i];
      if (p.range_m <= 0.0F) continue;
      const double t_s = core::ns_to_sec(scan.stamp_ns) + p.offset_us * 1e-6;
      // The buoy's bearing from the bow at the beam's own time.
      const double expected = core::wrap_deg(0.0 - rate_dps * t_s);
      EXPECT_LT(std::abs(core::wrap_deg(static_cast<double>(p.bearing_deg) - expected)), 3.5)
          << "point " << i;
      max_naive_error =
          std::max(max_naive_error,
                   std::abs(core::wrap_deg(static_cast<double>(p.bearing_deg) + heading_at_stamp)));
      EXPECT_GE(p.range_m, 5.69F);  // front of the buoy ...
      EXPECT_LE(p.range_m, 6.0F);   // ... to its flanks
      ++checked;
    }
  }
  EXPECT_GT(checked, 10);
  // Without de-skew the buoy would be misplaced: the boat turned up to 18 deg in a revolution.
  EXPECT_GT(max_naive_error, 5.0);
}

TEST(LidarSim, NoiseDropoutsAndSpuriousReturnsAtTheirRates) {
  LidarSimConfig c = quiet_config();
  c.range_sigma_m = 0.02;
  c.dropout_probability = 0.1;
  c.spurious_probability = 0.05;
  LidarSim sim(c, room());
  BoatTruth truth;
  int total = 0;
  int empty = 0;
  int near = 0;
  double sum_err2 = 0.0;
  int n_err = 0;
  for (core::TimeNs t = 0; t <= core::sec_to_ns(3.0); t += core::ms_to_ns(10)) {
    if (!sim.update(t, truth).raw_ready) continue;
    for (const RawBeam& b : sim.raw_revolution()) {
      ++total;
      if (b.range_m == 0.0F) {
        ++empty;
        continue;
      }
      if (static_cast<double>(b.range_m) < c.spurious_max_range_m) {
        ++near;
        continue;
      }
      const double truth_m = sim.true_range_m(truth.pose, static_cast<double>(b.angle_deg));
      const double err = static_cast<double>(b.range_m) - truth_m;
      sum_err2 += err * err;
      ++n_err;
    }
  }
  ASSERT_GT(total, 20000);
  EXPECT_NEAR(static_cast<double>(empty) / total, 0.1, 0.015);
  EXPECT_NEAR(static_cast<double>(near) / total, 0.05, 0.01);
  const double sigma = std::sqrt(sum_err2 / n_err);
  EXPECT_GT(sigma, 0.015);
  EXPECT_LT(sigma, 0.06);  // 0.02 + 0.5 % of 3-7 m
}

TEST(LidarSim, RayBinsStayNarrowAfterTheBoatJumps) {
  LidarSim sim(quiet_config(), room());
  BoatTruth truth;
  sim.update(0, truth);
  truth.pose.position = {3.0, -4.0};  // a reset of the simulation moves the boat at once
  sim.update(core::ms_to_ns(10), truth);
  EXPECT_GT(sim.scene().prepared_radius_m(), 4.0);
  for (core::TimeNs t = core::ms_to_ns(20); t <= core::ms_to_ns(200); t += core::ms_to_ns(10)) {
    truth.pose.position.north_m += 0.01;  // 1 m/s
    sim.update(t, truth);
  }
  EXPECT_LT(sim.scene().prepared_radius_m(), 0.5);
  // Each ray tests about as many objects as lie along it, not every object.
  EXPECT_LT(sim.scene().bin_entries(), 180U * 2U);
  // And the scan is still right: the wall 5 m north, seen from where the boat was at the time of
  // the bow beam (north = 3 m + 1 m/s since t = 10 ms).
  const msg::LidarScan& scan = sim.scan();
  const msg::LidarPoint* bow = nearest_bearing(scan, 0.0);
  const double t_s = core::ns_to_sec(scan.stamp_ns) + bow->offset_us * 1e-6;
  EXPECT_NEAR(bow->range_m, 5.0 - (3.0 + (t_s - 0.01)), 0.005);
}

TEST(LidarSim, DeterministicForASeed) {
  LidarSimConfig c = LidarSimConfig::for_model(LidarModel::kA2M8);
  c.seed = 99;
  LidarSim a(c, room());
  LidarSim b(c, room());
  BoatTruth truth;
  for (core::TimeNs t = 0; t <= core::ms_to_ns(500); t += core::ms_to_ns(10)) {
    a.update(t, truth);
    b.update(t, truth);
  }
  ASSERT_EQ(a.raw_revolution().size(), b.raw_revolution().size());
  for (std::size_t i = 0; i < a.raw_revolution().size(); ++i) {
    ASSERT_EQ(a.raw_revolution()[i].range_m, b.raw_revolution()[i].range_m);
  }
}

}  // namespace
}  // namespace coxswain::sim::sensors
