// SPDX-License-Identifier: Apache-2.0
// The navigation filter on real recordings (the shared test data; skipped when absent):
//  * a moving u-blox F9 rover whose fixes are mostly RTK fixed: the RTK fixed track is the truth;
//    each fix is degraded to single-point quality with the receiver's own single-point noise
//    (its hAcc and sAcc in the epochs it had no carrier solution, cycled), and the filter's track
//    is compared with the raw degraded fixes (median and p95 printed; the filter must be better).
//  * the source team's boat (myAHRS+ at 100 Hz, 1 Hz GNSS): the filter's heading against the
//    AHRS's, the gyro bias it finds, no real sample refused by the gates; the path lengths and
//    their heading node's difference from the AHRS are printed.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "coxswain/core/angles.hpp"
#include "coxswain/core/geodesy.hpp"
#include "coxswain/drivers/ublox/codec.hpp"
#include "coxswain/guidance/nav_filter.hpp"
#include "support/run_command.hpp"
#include "support/testdata.hpp"

namespace coxswain::guidance {
namespace {

std::vector<std::uint8_t> gunzip(const std::filesystem::path& p) {
  bool ok = false;
  std::vector<std::uint8_t> out = coxswain::test::gunzip(p, &ok);
  EXPECT_TRUE(ok) << "gzip -dc " << p;
  return out;
}

std::vector<msg::GnssFix> nav_pvt_fixes(const std::vector<std::uint8_t>& bytes) {
  std::vector<msg::GnssFix> fixes;
  drivers::ublox::Decoder d;
  std::span<const std::uint8_t> rest(bytes);
  while (!rest.empty()) {
    const drivers::DecodeStep step = d.decode(rest);
    rest = rest.subspan(step.consumed);
    if (step.produced && d.message().kind == drivers::ublox::MessageKind::kFix &&
        d.message().fix.source == msg::GnssSource::kUbxNavPvt && d.message().fix.utc_ns != 0) {
      fixes.push_back(d.message().fix);
    }
  }
  return fixes;
}

double quantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1))];
}

TEST(NavFilterRecordings, FilteredDegradedF9FixesTrackTheRtkTruthBetterThanTheRawOnes) {
  COXSWAIN_REQUIRE_TESTDATA(path, "gnss/ublox-f9p_rover-20190416-1617.ubx.gz");
  const std::vector<msg::GnssFix> fixes = nav_pvt_fixes(gunzip(path));
  ASSERT_GT(fixes.size(), 3000U);
  // The receiver's own single-point accuracy: its hAcc in the epochs without a carrier solution.
  std::vector<double> single_h_acc;
  for (const auto& f : fixes) {
    if (f.rtk == msg::RtkSolution::kNone && f.h_acc_m > 0.0) single_h_acc.push_back(f.h_acc_m);
  }
  ASSERT_GT(single_h_acc.size(), 100U);

  const core::LocalFrame frame({fixes.front().lat_deg, fixes.front().lon_deg, 0.0});
  std::mt19937_64 rng(20190416);
  std::normal_distribution<double> n01(0.0, 1.0);
  // The degradation is white noise around the RTK track: the filter is told so (no bias wander
  // to expect, a receiver-specific setting), as it would be told a receiver's own figures.
  NavFilterParams params;
  params.gnss_bias_wander_sigma_m = 0.05;
  NavFilter filter(params);
  std::vector<double> raw_err;
  std::vector<double> filt_err;
  std::size_t k = 0;
  for (const msg::GnssFix& f : fixes) {
    if (f.rtk != msg::RtkSolution::kFixed) continue;  // truth only where RTK fixed
    const core::NavPoint truth = frame.to_nav({f.lat_deg, f.lon_deg, 0.0});
    const double h = single_h_acc[k++ % single_h_acc.size()];
    const double sigma = h / std::sqrt(2.0);
    msg::GnssFix degraded = f;
    degraded.rtk = msg::RtkSolution::kNone;
    degraded.h_acc_m = h;
    degraded.vel_north_mps += 0.07 * n01(rng);  // the receiver's median sAcc
    degraded.vel_east_mps += 0.07 * n01(rng);
    const core::NavPoint fix{truth.north_m + sigma * n01(rng), truth.east_m + sigma * n01(rng)};
    (void)filter.add_fix(f.utc_ns, fix, degraded);
    raw_err.push_back(core::distance_m(fix, truth));
    filt_err.push_back(core::distance_m(filter.position(), truth));
  }
  ASSERT_GT(raw_err.size(), 3000U);
  const double raw_med = quantile(raw_err, 0.5);
  const double raw_p95 = quantile(raw_err, 0.95);
  const double filt_med = quantile(filt_err, 0.5);
  const double filt_p95 = quantile(filt_err, 0.95);
  std::printf(
      "F9 rover, %zu RTK fixed epochs degraded to single point (hAcc median %.3f m): error raw "
      "median %.3f m p95 %.3f m; filtered median %.3f m p95 %.3f m; %u fixes refused\n",
      raw_err.size(), quantile(single_h_acc, 0.5), raw_med, raw_p95, filt_med, filt_p95,
      filter.counters().fixes_rejected);
  EXPECT_LT(filt_med, raw_med);
  EXPECT_LT(filt_p95, raw_p95);
}

/// One CSV of the peer recording, gunzipped, as rows of numbers (the header line dropped; text
/// fields become NaN).
std::vector<std::vector<double>> read_csv(const std::filesystem::path& p) {
  const std::vector<std::uint8_t> bytes = gunzip(p);
  std::vector<std::vector<double>> rows;
  std::istringstream in(std::string(bytes.begin(), bytes.end()));
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    std::vector<double> row;
    std::istringstream ls(line);
    std::string cell;
    while (std::getline(ls, cell, ',')) {
      char* end = nullptr;
      const double v = std::strtod(cell.c_str(), &end);
      row.push_back(end != cell.c_str() ? v : std::nan(""));
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

TEST(NavFilterRecordings, OnThePeerBoatTheHeadingFollowsTheAhrsAndNoRealSampleIsRefused) {
  COXSWAIN_REQUIRE_TESTDATA(dir, "peer/tricat221-0429");
  const auto imu = read_csv(dir / "imu_data.csv.gz");
  const auto gps = read_csv(dir / "gps.csv.gz");
  const auto heading = read_csv(dir / "0429_heading.csv.gz");
  ASSERT_GT(imu.size(), 5000U);
  ASSERT_GT(gps.size(), 50U);
  ASSERT_GT(heading.size(), 500U);
  // The magnetometer heading is the myAHRS+'s own yaw (its orientation, east-north-up: heading
  // = 90 deg - yaw), as our driver reports it; no declination, so every heading here is
  // magnetic. Their heading node (0429_heading.csv) is printed beside it for comparison.
  const core::LocalFrame frame({gps.front()[6], gps.front()[7], 0.0});
  NavFilter filter;
  std::size_t hi = 0;
  std::size_t gi = 0;
  std::vector<double> heading_diff;
  std::vector<double> node_diff;
  std::vector<core::NavPoint> raw_track;
  std::vector<core::NavPoint> filt_track;
  for (const auto& row : imu) {
    const auto t = static_cast<core::TimeNs>(row[0]);
    while (hi + 1 < heading.size() && static_cast<core::TimeNs>(heading[hi + 1][0]) <= t) ++hi;
    // Their driver's angular velocity about z turns the same way as their heading (clockwise;
    // checked against the orientation's yaw); accelerations in m/s^2, y to port.
    const double yaw_rate_dps = row[19] * 180.0 / 3.14159265358979323846;
    const double ax_g = row[29] / 9.80665;
    const double ay_g = -row[30] / 9.80665;
    // Roll and pitch from the same specific force (the boat is nearly at rest): no net
    // acceleration, only the yaw rate and the heading drive the filter.
    const double pitch = std::asin(std::clamp(ax_g, -1.0, 1.0)) * 180.0 / 3.14159265358979323846;
    const double roll =
        -std::asin(std::clamp(ay_g / std::cos(pitch * 3.14159265358979323846 / 180.0), -1.0, 1.0)) *
        180.0 / 3.14159265358979323846;
    const double qx = row[4];
    const double qy = row[5];
    const double qz = row[6];
    const double qw = row[7];
    const double yaw_deg = std::atan2(2.0 * (qw * qz + qx * qy), 1.0 - 2.0 * (qy * qy + qz * qz)) *
                           180.0 / 3.14159265358979323846;
    const double ahrs_heading_deg = core::wrap_deg(90.0 - yaw_deg);
    filter.add_imu(t, ahrs_heading_deg, true, yaw_rate_dps, ax_g, ay_g, roll, pitch);
    if (filter.has_heading() && hi > 10) {
      heading_diff.push_back(std::abs(core::wrap_deg(filter.heading_deg() - ahrs_heading_deg)));
      node_diff.push_back(std::abs(core::wrap_deg(heading[hi][1] - ahrs_heading_deg)));
    }
    if (gi < gps.size() && static_cast<core::TimeNs>(gps[gi][0]) <= t) {
      const auto& g = gps[gi++];
      msg::GnssFix q;
      q.fix_ok = g[4] >= 0.0;
      q.fix_type = msg::FixType::k3D;
      q.h_acc_m = std::sqrt(g[9] + g[13]);  // the receiver's own variance east + north
      const core::NavPoint fix = frame.to_nav({g[6], g[7], 0.0});
      (void)filter.add_fix(t, fix, q);
      raw_track.push_back(fix);
      filt_track.push_back(filter.position());
    }
  }
  ASSERT_GT(raw_track.size(), 50U);
  auto path_length = [](const std::vector<core::NavPoint>& v) {
    double s = 0.0;
    for (std::size_t i = 1; i < v.size(); ++i) s += core::distance_m(v[i - 1], v[i]);
    return s;
  };
  const double med = quantile(heading_diff, 0.5);
  const double p95 = quantile(heading_diff, 0.95);
  std::printf(
      "tricat221 0429: heading vs the AHRS median %.2f deg p95 %.2f deg (their heading node vs "
      "the AHRS: median %.1f deg p95 %.1f deg); gyro bias %.3f deg/s; %u headings refused; path "
      "raw %.1f m, filtered %.1f m; %u fixes refused\n",
      med, p95, quantile(node_diff, 0.5), quantile(node_diff, 0.95), filter.yaw_rate_bias_dps(),
      filter.counters().mag_rejected, path_length(raw_track), path_length(filt_track),
      filter.counters().fixes_rejected);
  EXPECT_LT(med, 2.0);
  EXPECT_LT(p95, 6.0);
  EXPECT_LT(std::abs(filter.yaw_rate_bias_dps()), 1.0);
  // Real fixes of a boat nearly at rest are not outliers, and the heading is never lost.
  EXPECT_EQ(filter.counters().fixes_rejected, 0U);
  EXPECT_EQ(filter.counters().mag_rejected, 0U);
}

}  // namespace
}  // namespace coxswain::guidance
