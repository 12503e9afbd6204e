// SPDX-License-Identifier: Apache-2.0
// Protobuf encoding of the recording: every message round-trips field for field (checked through
// the legacy packed encoder, whose bytes are the fields in order), the largest messages fit the
// recorder's slots, absent fields read as defaults, malformed input is refused without reading
// past its end, and FORMAT.md quotes the .proto the descriptors describe.
#include <gtest/gtest.h>

#include <bit>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include "coxswain/record/proto_codec.hpp"
#include "sample_messages.hpp"

namespace coxswain::record {
namespace {

// Equal legacy encodings = equal fields (the packed layout is every field in order, no padding).
template <class T>
void expect_same_fields(const T& a, const T& b) {
  std::vector<std::uint8_t> ea(kMaxLidarBytes), eb(kMaxLidarBytes);
  const std::size_t na = encode_sample(ea, 1, a);
  const std::size_t nb = encode_sample(eb, 1, b);
  ASSERT_GT(na, 0U);
  EXPECT_EQ(na, nb);
  EXPECT_TRUE(ea == eb);
}

template <class T>
void expect_round_trip(const T& m, std::size_t max_bytes) {
  std::vector<std::uint8_t> buf(max_bytes);
  const std::size_t n = proto::encode_sample(buf, 987654321, m);
  ASSERT_GT(n, 0U) << "does not fit " << max_bytes << " bytes";
  auto back = std::make_unique<T>();
  std::uint64_t sequence = 0;
  ASSERT_TRUE(proto::decode_sample(std::span(buf).first(n), sequence, *back));
  EXPECT_EQ(sequence, 987654321U);
  expect_same_fields(m, *back);
  // Either encoding through the channel's dispatch.
  ASSERT_TRUE(decode_sample(Encoding::kProtobuf, std::span(buf).first(n), sequence, *back));
  expect_same_fields(m, *back);
}

constexpr std::size_t kSampleSlotBytes = 1024;  // the recorder's slot for a small message

std::unique_ptr<msg::LidarScan> full_scan() {
  auto scan = std::make_unique<msg::LidarScan>();
  scan->stamp_ns = 10;
  scan->duration_ns = 100'000'000;
  scan->max_range_m = 12.0F;
  scan->min_range_m = 0.15F;
  scan->revolution = 42;
  for (std::size_t i = 0; i < msg::LidarScan::kMaxPoints; ++i) {
    // The widest values: quality 255, offsets of either sign far from zero.
    const auto offset = static_cast<std::int32_t>(i % 2 == 0 ? -2'000'000'000 : 2'000'000'000);
    EXPECT_TRUE(scan->push(
        {static_cast<float>(i) * 0.05F - 100.0F, 1.0F + static_cast<float>(i % 7), 255, offset}));
  }
  return scan;
}

msg::CameraDetections full_camera() {
  msg::CameraDetections cam;
  cam.stamp_ns = -11;
  cam.frame_index = 0xFFFFFFFF;
  cam.image_width_px = 65535;
  cam.image_height_px = 480;
  for (std::size_t i = 0; i < msg::CameraDetections::kMaxDetections; ++i) {
    EXPECT_TRUE(
        cam.push({msg::Colour::kRed, msg::Shape::kTriangle, -12.5F, 100, 200, 30, 40, 900, 0.9F}));
  }
  return cam;
}

TEST(ProtoCodec, EveryDecodedMessageRoundTripsFieldForFieldWithinItsSlot) {
  expect_round_trip(make_fix(), kSampleSlotBytes);
  msg::ImuSample imu;
  imu.stamp_ns = 5;
  imu.roll_deg = 1.0;
  imu.heading_deg = -170.25;
  imu.accel_g = {0.1, 0.2, 0.98};
  imu.gyro_dps = {-1.5, 0.0, 3.25};
  imu.mag_ut = {30, -20, 40};
  imu.temperature_c = 31.5;
  imu.has_inertial = true;
  imu.sequence = 0xFFFFFFFF;
  expect_round_trip(imu, kSampleSlotBytes);
  expect_round_trip(*full_scan(), proto::kMaxLidarBytes);
  expect_round_trip(full_camera(), kSampleSlotBytes);
  msg::ArduinoStatus ard;
  ard.stamp_ns = 12;
  ard.applied_pulse_us = {1600, 65535};
  ard.mode = msg::ControlMode::kAutonomous;
  ard.estop = true;
  ard.rc_present = true;
  ard.supply_v = 12.6;
  ard.last_sequence_seen = 65535;
  expect_round_trip(ard, kSampleSlotBytes);
  msg::OperatorInput op;
  op.start_count = 2;
  op.hold = true;
  op.target_colour = msg::Colour::kBlue;
  expect_round_trip(op, kSampleSlotBytes);
  expect_round_trip(make_health(msg::DeviceId::kGnss), kSampleSlotBytes);
}

TEST(ProtoCodec, AFullTickFitsItsBoundAndRoundTrips) {
  auto snap = std::make_unique<core::Snapshot>();
  snap->lidar = {*full_scan(), 1000, 31};
  snap->gnss = {make_fix(), 2000, 12};
  snap->imu.sequence = 400;
  snap->imu.value.heading_deg = 45.0;
  snap->camera = {full_camera(), 3000, 5};
  fill_health(*snap);
  const msg::ActuatorCommand cmd = make_command();
  const std::string path(400, 'p');  // longer than kept
  std::vector<std::uint8_t> buf(proto::kMaxTickBytes);
  const std::size_t n = proto::encode_tick(buf, 17, 5000, *snap, cmd, path);
  ASSERT_GT(n, 0U) << "a full tick must fit proto::kMaxTickBytes";
  auto back = std::make_unique<TickRecordData>();
  ASSERT_TRUE(decode_tick(Encoding::kProtobuf, std::span(buf).first(n), *back));
  EXPECT_EQ(back->state_path, path.substr(0, kMaxStatePathBytes));
  // The whole tick, field for field: both ticks in the legacy layout.
  std::vector<std::uint8_t> a(kMaxTickBytes), b(kMaxTickBytes);
  snap->lidar.value.point_count = back->snapshot.lidar.value.point_count;  // header only
  const std::size_t na = encode_tick(a, 17, 5000, *snap, cmd, back->state_path);
  const std::size_t nb = encode_tick(b, back->tick_index, back->now_ns, back->snapshot,
                                     back->command, back->state_path);
  ASSERT_GT(na, 0U);
  EXPECT_EQ(na, nb);
  EXPECT_TRUE(a == b);
  EXPECT_EQ(back->snapshot.lidar.value.point_count, msg::LidarScan::kMaxPoints);
  EXPECT_FALSE(back->snapshot.operator_input.valid());
  EXPECT_FALSE(decode_tick(Encoding::kProtobuf, std::span(buf).first(n - 1), *back));
  // A recording from before protobuf: the legacy layout through the same dispatch.
  ASSERT_TRUE(decode_tick(Encoding::kLegacyBinary, std::span(a).first(na), *back));
  EXPECT_EQ(back->snapshot.gnss.value.lat_deg, make_fix().lat_deg);
}

TEST(ProtoCodec, RawBytesAndParameterSetsRoundTrip) {
  std::vector<std::uint8_t> bytes(1024);
  for (std::size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<std::uint8_t>(i * 7);
  std::vector<std::uint8_t> buf(1024 + proto::kMaxRawOverheadBytes);
  const RawRecord raw{msg::DeviceId::kArduino, drivers::RawDirection::kToDevice, -777, bytes};
  const std::size_t n = proto::encode_raw(buf, raw);
  ASSERT_GT(n, 0U);
  RawRecord back;
  ASSERT_TRUE(decode_raw(Encoding::kProtobuf, std::span(buf).first(n), back));
  EXPECT_EQ(back.device, msg::DeviceId::kArduino);
  EXPECT_EQ(back.direction, drivers::RawDirection::kToDevice);
  EXPECT_EQ(back.stamp_ns, -777);
  EXPECT_TRUE(std::equal(back.bytes.begin(), back.bytes.end(), bytes.begin(), bytes.end()));
  EXPECT_FALSE(proto::decode_raw(std::span(buf).first(n - 1), back));
  EXPECT_EQ(proto::encode_raw(std::span(buf).first(10), raw), 0U);  // too small: nothing

  const NamedValue values[] = {{"heading_pid.kp_per_deg", 0.1 + 0.2},
                               {"avoidance.strategy", 2.0},
                               {"vision.red.h_min", 170.0}};
  std::vector<std::uint8_t> pbuf(proto::kMaxParameterBytes);
  const std::size_t pn = proto::encode_parameters(pbuf, 1234, -5, values);
  ASSERT_GT(pn, 0U);
  ParameterSetRecord set;
  ASSERT_TRUE(decode_parameters(Encoding::kProtobuf, std::span(pbuf).first(pn), set));
  EXPECT_EQ(set.tick_index, 1234U);
  EXPECT_EQ(set.stamp_ns, -5);
  ASSERT_EQ(set.values.size(), 3U);
  EXPECT_EQ(set.values[0].first, "heading_pid.kp_per_deg");
  EXPECT_EQ(set.values[0].second, 0.1 + 0.2);  // every bit
  EXPECT_EQ(set.values[2].second, 170.0);
  const std::string long_name(300, 'x');
  const NamedValue too_long[] = {{long_name, 1.0}};
  EXPECT_EQ(proto::encode_parameters(pbuf, 1, 0, too_long), 0U);
}

TEST(ProtoCodec, AbsentFieldsReadAsDefaultsEvenIntoAReusedMessage) {
  // Only field 1 (store_sequence = 5) and field 8 (lat_deg = 1.5): another writer's, or an
  // older, message.
  std::vector<std::uint8_t> msg = {0x08, 0x05, 0x41};
  const double lat = 1.5;
  const auto bits = std::bit_cast<std::uint64_t>(lat);
  for (int i = 0; i < 8; ++i) msg.push_back(static_cast<std::uint8_t>(bits >> (8 * i)));
  msg::GnssFix fix = make_fix();  // reused: every field set
  std::uint64_t sequence = 0;
  ASSERT_TRUE(proto::decode_sample(std::span<const std::uint8_t>(msg), sequence, fix));
  EXPECT_EQ(sequence, 5U);
  EXPECT_EQ(fix.lat_deg, 1.5);
  EXPECT_EQ(fix.lon_deg, msg::GnssFix{}.lon_deg);
  EXPECT_EQ(fix.s_acc_mps, -1.0);  // unknown: the struct's default, not the reused value
  EXPECT_EQ(fix.satellites, 0U);
}

TEST(ProtoCodec, MalformedMessagesAreRefusedWithoutReadingPastTheirEnd) {
  std::vector<std::uint8_t> buf(kSampleSlotBytes);
  const msg::DeviceHealth h = make_health(msg::DeviceId::kLidar);
  const std::size_t n = proto::encode_sample(buf, 3, h);
  ASSERT_GT(n, 0U);
  std::uint64_t sequence = 0;
  msg::DeviceHealth back;
  // Every prefix and every single-byte change decodes or is refused; under the sanitizers a
  // read past the end fails this test.
  for (std::size_t cut = 0; cut < n; ++cut) {
    std::vector<std::uint8_t> prefix(buf.begin(), buf.begin() + static_cast<long>(cut));
    (void)proto::decode_sample(std::span<const std::uint8_t>(prefix), sequence, back);
  }
  for (std::size_t i = 0; i < n; ++i) {
    std::vector<std::uint8_t> changed(buf.begin(), buf.begin() + static_cast<long>(n));
    changed[i] ^= 0xFF;
    (void)proto::decode_sample(std::span<const std::uint8_t>(changed), sequence, back);
  }
  // A field with the wrong wire type, a value out of its type's range, a group, a field 0.
  const std::vector<std::vector<std::uint8_t>> bad = {
      {0x0D, 0, 0, 0, 0},  // store_sequence as fixed32
      {0x18, 0x80, 0x02},  // device = 256 (an 8-bit enum)
      {0x0B},              // group start
      {0x00, 0x01},        // field number 0
      {0x08, 0x80},        // varint cut short
      {0x12, 0x05, 0x01},  // length past the end
  };
  for (const auto& m : bad) {
    EXPECT_FALSE(proto::decode_sample(std::span<const std::uint8_t>(m), sequence, back))
        << "accepted " << m.size() << " bytes starting " << static_cast<int>(m[0]);
  }
  // A scan whose columns disagree with its point count.
  auto scan = std::make_unique<msg::LidarScan>();
  ASSERT_TRUE(scan->push({1.0F, 2.0F, 3, 4}));
  ASSERT_TRUE(scan->push({5.0F, 6.0F, 7, 8}));
  std::vector<std::uint8_t> sbuf(256);
  const std::size_t sn = proto::encode_sample(sbuf, 1, *scan);
  auto sback = std::make_unique<msg::LidarScan>();
  ASSERT_TRUE(proto::decode_sample(std::span(sbuf).first(sn), sequence, *sback));
  EXPECT_EQ(sback->point_count, 2U);
  // Rewrite the header count to 3 over a two-point encoding: field 7 (point_count) is a varint.
  std::vector<std::uint8_t> patched(sbuf.begin(), sbuf.begin() + static_cast<long>(sn));
  for (std::size_t i = 0; i + 1 < patched.size(); ++i) {
    if (patched[i] == 0x38 && patched[i + 1] == 0x02) {
      patched[i + 1] = 0x03;
      break;
    }
  }
  EXPECT_FALSE(proto::decode_sample(std::span<const std::uint8_t>(patched), sequence, *sback));
}

TEST(ProtoCodec, TheDescriptorsNameEveryChannelTypeAndFormatMdQuotesThem) {
  const std::string& text = recording_proto_text();
  for (Layout l :
       {Layout::kRaw, Layout::kTick, Layout::kGnss, Layout::kImu, Layout::kLidar, Layout::kCamera,
        Layout::kArduino, Layout::kOperator, Layout::kHealth, Layout::kParameters}) {
    const std::string name(proto_message_name(l));
    ASSERT_TRUE(name.starts_with("coxswain."));
    EXPECT_NE(text.find("message " + name.substr(9) + " {"), std::string::npos) << name;
    EXPECT_NE(file_descriptor_set(l).find(name.substr(9)), std::string::npos) << name;
  }
  EXPECT_NE(text.find("repeated float bearing_deg = 8;"), std::string::npos) << text;
  EXPECT_NE(text.find("repeated .coxswain.Tick.Health health = 11;"), std::string::npos);
  std::ifstream in(std::string(COXSWAIN_SOURCE_DIR) + "/src/record/FORMAT.md");
  ASSERT_TRUE(in) << "src/record/FORMAT.md missing";
  const std::string doc{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  EXPECT_NE(doc.find(text), std::string::npos)
      << "FORMAT.md does not quote the recording's .proto verbatim; it reads:\n"
      << text;
}

}  // namespace
}  // namespace coxswain::record
