// SPDX-License-Identifier: Apache-2.0
// Binary layouts: every message round-trips field for field, a full tick fits kMaxTickBytes, and
// FORMAT.md documents exactly the layouts the code writes.
#include <gtest/gtest.h>

#include <bit>
#include <cstring>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include "coxswain/record/layouts.hpp"
#include "sample_messages.hpp"

namespace coxswain::record {
namespace {

template <class T>
bool same_bytes(const T& a, const T& b) {
  // Padding-free comparison through the encoder: equal encodings = equal fields.
  std::vector<std::uint8_t> ea(kMaxLidarBytes), eb(kMaxLidarBytes);
  return encode_sample(ea, 1, a) == encode_sample(eb, 1, b) && ea == eb;
}

TEST(Layouts, AGnssFixOfTheFirstVersionReadsWithoutASpeedAccuracy) {
  // Version 1 had no s_acc_mps: the same bytes without its last field, version byte 1.
  std::vector<std::uint8_t> buf(kMaxLidarBytes);
  const std::size_t n = encode_sample(buf, 3, make_fix());
  ASSERT_EQ(buf[0], 2);
  buf[0] = 1;
  std::uint64_t seq = 0;
  msg::GnssFix old;
  ASSERT_TRUE(decode_sample(std::span(buf).first(n - 8), seq, old));
  EXPECT_EQ(old.s_acc_mps, -1.0);  // unknown, the struct's default
  EXPECT_EQ(old.itow_ms, make_fix().itow_ms);
  // The current version needs the field; a version from the future is refused.
  EXPECT_FALSE(decode_sample(std::span(buf).first(n - 8).subspan(0, n - 9), seq, old));
  buf[0] = 3;
  EXPECT_FALSE(decode_sample(std::span(buf).first(n), seq, old));
}

TEST(Layouts, TheSchemaTextComesFromTheFieldListAndNamesEveryField) {
  const std::string gnss(layout_schema_text(Layout::kGnss));
  EXPECT_NE(gnss.find("coxswain.GnssFix v2"), std::string::npos);
  EXPECT_NE(gnss.find("f64 lat_deg; f64 lon_deg;"), std::string::npos);
  EXPECT_NE(gnss.find("f64 s_acc_mps (since v2)"), std::string::npos);
  const std::string imu(layout_schema_text(Layout::kImu));
  EXPECT_NE(imu.find("f64[3] accel_g"), std::string::npos);
  const std::string lidar(layout_schema_text(Layout::kLidar));
  EXPECT_NE(lidar.find("point_count x (f32 bearing_deg (body frame); f32 range_m"),
            std::string::npos);
}

TEST(Layouts, DecodedMessagesRoundTrip) {
  std::vector<std::uint8_t> buf(kMaxLidarBytes);
  std::uint64_t seq = 0;

  const msg::GnssFix fix = make_fix();
  msg::GnssFix fix2;
  ASSERT_TRUE(decode_sample(std::span(buf).first(encode_sample(buf, 7, fix)), seq, fix2));
  EXPECT_EQ(seq, 7U);
  EXPECT_EQ(fix2.lat_deg, fix.lat_deg);
  EXPECT_EQ(fix2.utc_ns, fix.utc_ns);
  EXPECT_EQ(fix2.rtk, fix.rtk);
  EXPECT_EQ(fix2.s_acc_mps, fix.s_acc_mps);
  EXPECT_TRUE(same_bytes(fix, fix2));

  msg::ImuSample imu;
  imu.stamp_ns = 5;
  imu.roll_deg = 1.0;
  imu.heading_deg = -170.25;
  imu.accel_g = {0.1, 0.2, 0.98};
  imu.mag_ut = {30, -20, 40};
  imu.has_inertial = true;
  imu.sequence = 77;
  msg::ImuSample imu2;
  ASSERT_TRUE(decode_sample(std::span(buf).first(encode_sample(buf, 8, imu)), seq, imu2));
  EXPECT_EQ(imu2.heading_deg, imu.heading_deg);
  EXPECT_EQ(imu2.accel_g, imu.accel_g);
  EXPECT_EQ(imu2.sequence, 77U);

  auto scan = std::make_unique<msg::LidarScan>();
  scan->stamp_ns = 10;
  scan->duration_ns = 100'000'000;
  scan->max_range_m = 12.0F;
  scan->revolution = 42;
  for (std::size_t i = 0; i < msg::LidarScan::kMaxPoints; ++i) {
    ASSERT_TRUE(
        scan->push({static_cast<float>(i) * 0.05F - 100.0F, 1.0F + static_cast<float>(i % 7),
                    static_cast<std::uint8_t>(i), static_cast<std::int32_t>(i * 25)}));
  }
  const std::size_t n = encode_sample(buf, 9, *scan);
  ASSERT_GT(n, 0U);
  ASSERT_LE(n, kMaxLidarBytes);
  auto scan2 = std::make_unique<msg::LidarScan>();
  ASSERT_TRUE(decode_sample(std::span(buf).first(n), seq, *scan2));
  ASSERT_EQ(scan2->point_count, scan->point_count);
  EXPECT_EQ(scan2->points[4095].offset_us, scan->points[4095].offset_us);
  EXPECT_EQ(scan2->points[100].bearing_deg, scan->points[100].bearing_deg);
  EXPECT_EQ(scan2->revolution, 42U);
  // A truncated message is rejected, never read past its end.
  EXPECT_FALSE(decode_sample(std::span(buf).first(n - 1), seq, *scan2));

  msg::CameraDetections cam;
  cam.stamp_ns = 11;
  cam.frame_index = 3;
  cam.image_width_px = 640;
  cam.image_height_px = 480;
  ASSERT_TRUE(
      cam.push({msg::Colour::kRed, msg::Shape::kTriangle, -12.5F, 100, 200, 30, 40, 900, 0.9F}));
  msg::CameraDetections cam2;
  ASSERT_TRUE(decode_sample(std::span(buf).first(encode_sample(buf, 1, cam)), seq, cam2));
  ASSERT_EQ(cam2.count, 1U);
  EXPECT_EQ(cam2.detections[0].shape, msg::Shape::kTriangle);
  EXPECT_EQ(cam2.detections[0].bearing_deg, -12.5F);

  msg::ArduinoStatus ard;
  ard.stamp_ns = 12;
  ard.applied_pulse_us = {1600, 1400};
  ard.mode = msg::ControlMode::kAutonomous;
  ard.estop = true;
  ard.supply_v = 12.6;
  ard.last_sequence_seen = 65535;
  msg::ArduinoStatus ard2;
  ASSERT_TRUE(decode_sample(std::span(buf).first(encode_sample(buf, 1, ard)), seq, ard2));
  EXPECT_EQ(ard2.applied_pulse_us, ard.applied_pulse_us);
  EXPECT_TRUE(ard2.estop);
  EXPECT_EQ(ard2.last_sequence_seen, 65535);

  msg::OperatorInput op;
  op.start_count = 2;
  op.hold = true;
  op.target_colour = msg::Colour::kBlue;
  msg::OperatorInput op2;
  ASSERT_TRUE(decode_sample(std::span(buf).first(encode_sample(buf, 1, op)), seq, op2));
  EXPECT_EQ(op2.start_count, 2U);
  EXPECT_EQ(op2.target_colour, msg::Colour::kBlue);

  const msg::DeviceHealth h = make_health(msg::DeviceId::kGnss);
  msg::DeviceHealth h2;
  ASSERT_TRUE(decode_sample(std::span(buf).first(encode_sample(buf, 1, h)), seq, h2));
  EXPECT_EQ(h2.detail_text(), h.detail_text());
  EXPECT_EQ(h2.frames_ok, 1000U);
  EXPECT_EQ(h2.device, msg::DeviceId::kGnss);

  // Unknown layout versions are refused.
  buf[0] = 2;
  EXPECT_FALSE(decode_sample(std::span(buf).first(10), seq, op2));
}

TEST(Layouts, RawRoundTripAndBounds) {
  const std::vector<std::uint8_t> bytes{0xA5, 0x5A, 0x05, 0x00};
  std::vector<std::uint8_t> buf(64);
  const RawRecord raw{msg::DeviceId::kArduino, drivers::RawDirection::kToDevice, 777, bytes};
  const std::size_t n = encode_raw(buf, raw);
  ASSERT_EQ(n, 16U + bytes.size());
  RawRecord back;
  ASSERT_TRUE(decode_raw(std::span(buf).first(n), back));
  EXPECT_EQ(back.device, msg::DeviceId::kArduino);
  EXPECT_EQ(back.direction, drivers::RawDirection::kToDevice);
  EXPECT_EQ(back.stamp_ns, 777);
  EXPECT_TRUE(std::equal(back.bytes.begin(), back.bytes.end(), bytes.begin(), bytes.end()));
  EXPECT_FALSE(decode_raw(std::span(buf).first(n - 1), back));
  EXPECT_EQ(encode_raw(std::span(buf).first(10), raw), 0U);  // too small: nothing, no overrun
}

TEST(Layouts, FullTickFitsAndRoundTrips) {
  auto snap = std::make_unique<core::Snapshot>();
  snap->lidar.sequence = 31;
  snap->lidar.stamp_ns = 1000;
  snap->lidar.value.point_count = 4000;
  snap->lidar.value.revolution = 30;
  snap->gnss = {make_fix(), 2000, 12};
  snap->imu.sequence = 400;
  snap->imu.value.heading_deg = 45.0;
  for (std::size_t i = 0; i < msg::CameraDetections::kMaxDetections; ++i) {
    ASSERT_TRUE(snap->camera.value.push(
        {msg::Colour::kGreen, msg::Shape::kCircle, 1.0F, 2, 3, 4, 5, 6, 0.5F}));
  }
  snap->camera.sequence = 5;
  fill_health(*snap);
  const msg::ActuatorCommand cmd = make_command();
  const std::string path(400, 'p');  // longer than kept
  std::vector<std::uint8_t> buf(kMaxTickBytes);
  const std::size_t n = encode_tick(buf, 17, 5000, *snap, cmd, path);
  ASSERT_GT(n, 0U) << "a full tick must fit kMaxTickBytes";
  auto back = std::make_unique<TickRecordData>();
  ASSERT_TRUE(decode_tick(std::span(buf).first(n), *back));
  EXPECT_EQ(back->tick_index, 17U);
  EXPECT_EQ(back->now_ns, 5000);
  EXPECT_EQ(back->state_path.size(), kMaxStatePathBytes);
  EXPECT_EQ(back->command.pulse_us, cmd.pulse_us);
  EXPECT_TRUE(back->command.active);
  EXPECT_EQ(back->snapshot.lidar.sequence, 31U);
  EXPECT_EQ(back->snapshot.lidar.value.point_count, 4000U);
  EXPECT_EQ(back->snapshot.gnss.sequence, 12U);
  EXPECT_EQ(back->snapshot.gnss.value.lat_deg, make_fix().lat_deg);
  EXPECT_EQ(back->snapshot.imu.value.heading_deg, 45.0);
  EXPECT_EQ(back->snapshot.camera.value.count, msg::CameraDetections::kMaxDetections);
  EXPECT_EQ(back->snapshot.health[4].sequence, 5U);
  EXPECT_EQ(back->snapshot.health[4].value.device, msg::DeviceId::kCamera);
  EXPECT_FALSE(back->snapshot.operator_input.valid());
  EXPECT_FALSE(decode_tick(std::span(buf).first(n - 1), *back));
}

TEST(Layouts, ParameterSetRoundTripsEveryBitAndRejectsWhatDoesNotFit) {
  const NamedValue values[] = {{"heading_pid.kp_per_deg", 0.1 + 0.2},
                               {"avoidance.strategy", 2.0},
                               {"vision.red.h_min", 170.0}};
  std::vector<std::uint8_t> buf(kMaxParameterBytes);
  const std::size_t n = encode_parameters(buf, 1234, -5, values);
  ASSERT_GT(n, 0U);
  ParameterSetRecord back;
  ASSERT_TRUE(decode_parameters(std::span(buf).first(n), back));
  EXPECT_EQ(back.tick_index, 1234U);
  EXPECT_EQ(back.stamp_ns, -5);
  ASSERT_EQ(back.values.size(), 3U);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(back.values[i].first, values[i].name);
    EXPECT_EQ(std::bit_cast<std::uint64_t>(back.values[i].second),
              std::bit_cast<std::uint64_t>(values[i].value));
  }
  EXPECT_FALSE(decode_parameters(std::span(buf).first(n - 1), back));
  EXPECT_EQ(encode_parameters(std::span(buf).first(20), 1, 0, values), 0U);  // too small
  const std::string long_name(300, 'x');
  const NamedValue too_long[] = {{long_name, 1.0}};
  EXPECT_EQ(encode_parameters(buf, 1, 0, too_long), 0U);
}

TEST(Layouts, FormatDocumentHoldsEveryLayoutText) {
  std::ifstream in(std::string(COXSWAIN_SOURCE_DIR) + "/src/record/FORMAT.md");
  ASSERT_TRUE(in) << "src/record/FORMAT.md missing";
  const std::string doc{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  for (Layout l :
       {Layout::kRaw, Layout::kTick, Layout::kGnss, Layout::kImu, Layout::kLidar, Layout::kCamera,
        Layout::kArduino, Layout::kOperator, Layout::kHealth, Layout::kParameters}) {
    EXPECT_NE(doc.find(std::string(layout_schema_text(l))), std::string::npos)
        << layout_schema_name(l) << " is not documented verbatim in FORMAT.md; it reads:\n"
        << layout_schema_text(l);
  }
}

}  // namespace
}  // namespace coxswain::record
