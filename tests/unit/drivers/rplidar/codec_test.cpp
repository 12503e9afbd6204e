// SPDX-License-Identifier: Apache-2.0
// Hand-built RPLIDAR answer streams (docs/protocols.md 1.4-1.9): no raw standard-mode capture
// exists, so every byte here is built from the protocol tables. These tests always run.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "coxswain/drivers/rplidar/answer_encoder.hpp"
#include "coxswain/drivers/rplidar/codec.hpp"
#include "decode_helpers.hpp"

namespace coxswain::drivers::rplidar {
namespace {

using Bytes = std::vector<std::uint8_t>;

struct NodeSpec {
  bool start;
  std::uint8_t quality;
  std::uint16_t angle_q6;
  std::uint16_t dist_q2;
};

// A deterministic revolution-like sequence of standard nodes: ~0.58 deg per sample, typical
// qualities, some samples without a return, the S flag where the angle wraps.
std::vector<NodeSpec> make_nodes(std::size_t n, std::size_t first = 0) {
  std::vector<NodeSpec> v;
  for (std::size_t i = first; i < first + n; ++i) {
    const std::size_t raw = i * 37 + (i % 3);
    const bool no_return = i % 17 == 0;
    v.push_back({raw % 23040 < 37, static_cast<std::uint8_t>(no_return ? 0 : 40 + i % 10),
                 static_cast<std::uint16_t>(raw % 23040),
                 static_cast<std::uint16_t>(no_return ? 0 : 8000 + (i * 53) % 16000)});
  }
  return v;
}

Bytes node_stream(const std::vector<NodeSpec>& nodes) {
  Bytes s;
  test::append(s, encode_descriptor(AnswerType::kMeasurement));
  for (const NodeSpec& n : nodes) {
    test::append(s, encode_standard_node(n.start, n.quality, n.angle_q6, n.dist_q2));
  }
  return s;
}

HqNode expected_hq(const NodeSpec& n) {
  HqNode h;
  h.angle_z_q14 = static_cast<std::uint16_t>((n.angle_q6 * 256U) / 90U);
  h.dist_mm_q2 = n.dist_q2;
  h.quality = static_cast<std::uint8_t>(n.quality << 2U);
  h.flag = n.start ? 1 : 0;
  return h;
}

TEST(RplidarCodec, StandardNodesDecodeToSdkHqForm) {
  const auto nodes = make_nodes(300);
  Decoder d;
  d.expect(AnswerType::kMeasurement);
  const auto got = test::decode_all(d, node_stream(nodes));
  ASSERT_EQ(got.nodes.size(), nodes.size());
  for (std::size_t i = 0; i < nodes.size(); ++i)
    EXPECT_EQ(got.nodes[i], expected_hq(nodes[i])) << i;
  EXPECT_EQ(d.stream_type(), AnswerType::kMeasurement);
  EXPECT_EQ(d.stats().codec.frames_ok, nodes.size());
  EXPECT_EQ(d.stats().codec.messages_out, nodes.size());
  EXPECT_EQ(d.stats().nodes_out, nodes.size());
  EXPECT_EQ(d.stats().codec.framing_errors, 0U);
  EXPECT_EQ(d.stats().codec.bytes_skipped, 0U);
}

TEST(RplidarCodec, HqConversionMatchesSdkFormula) {
  // 90 deg = q6 5760 -> z_q14 16384; 359.984 deg = q6 23039 -> (23039*256)/90 = 65533.
  EXPECT_EQ(hq_from_standard(0x02, (5760 << 1) | 1, 400).angle_z_q14, 16384);
  EXPECT_EQ(hq_from_standard(0x02, (23039 << 1) | 1, 400).angle_z_q14, 65533);
  EXPECT_EQ(hq_from_standard(0xFD, 1, 0).quality, 0xFC);
  EXPECT_EQ(hq_from_standard(0xFD, 1, 0).flag, 1);
  EXPECT_NEAR(hq_from_standard(0x02, (5760 << 1) | 1, 4000).angle_deg(), 90.0, 1e-9);
  EXPECT_NEAR(hq_from_standard(0x02, 1, 4001).distance_mm(), 1000.25, 1e-9);
}

TEST(RplidarCodec, GarbageBeforeDescriptorIsSkippedAndCounted) {
  const auto nodes = make_nodes(20);
  Bytes s = {0x00, 0xA5, 0x13, 'R', 'P', 0xA5, 0xA5};  // banner-like junk, false sync starts
  test::append(s, node_stream(nodes));
  Decoder d;
  d.expect(AnswerType::kMeasurement);
  const auto got = test::decode_all(d, s);
  ASSERT_EQ(got.nodes.size(), nodes.size());
  EXPECT_EQ(got.nodes.front(), expected_hq(nodes.front()));
  EXPECT_EQ(d.stats().codec.bytes_skipped, 7U);
}

TEST(RplidarCodec, BadCheckBitsDropOneNodeAndResync) {
  const auto nodes = make_nodes(40);
  Bytes s = node_stream(nodes);
  // Node 10: clear the C bit. Node 20: make S == !S. Both must be dropped, nothing else.
  s[kDescriptorSize + 10 * kNodeSize + 1] &= 0xFE;
  s[kDescriptorSize + 20 * kNodeSize + 0] |= 0x03;
  Decoder d;
  d.expect(AnswerType::kMeasurement);
  const auto got = test::decode_all(d, s);
  std::vector<HqNode> want;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (i != 10 && i != 20) want.push_back(expected_hq(nodes[i]));
  }
  ASSERT_EQ(got.nodes.size(), want.size());
  for (std::size_t i = 0; i < want.size(); ++i) EXPECT_EQ(got.nodes[i], want[i]) << i;
  EXPECT_GE(d.stats().node_check_errors, 2U);
  EXPECT_GE(d.stats().codec.framing_errors, 2U);
  EXPECT_GT(d.stats().codec.bytes_skipped, 0U);
}

TEST(RplidarCodec, InsertedJunkByteLosesNoRealNode) {
  const auto nodes = make_nodes(30);
  Bytes s;
  test::append(s, encode_descriptor(AnswerType::kMeasurement));
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const NodeSpec& n = nodes[i];
    test::append(s, encode_standard_node(n.start, n.quality, n.angle_q6, n.dist_q2));
    if (i == 7) s.push_back(0x00);   // fails the S/!S check
    if (i == 15) s.push_back(0x01);  // passes S/!S, then the next real byte fails C
  }
  Decoder d;
  d.expect(AnswerType::kMeasurement);
  const auto got = test::decode_all(d, s);
  ASSERT_EQ(got.nodes.size(), nodes.size());
  for (std::size_t i = 0; i < nodes.size(); ++i)
    EXPECT_EQ(got.nodes[i], expected_hq(nodes[i])) << i;
  EXPECT_EQ(d.stats().codec.bytes_skipped, 2U);
}

Bytes single_answers() {
  Bytes s;
  DeviceInfo info;
  info.model = 0x18;
  info.firmware_major = 1;
  info.firmware_minor = 29;
  info.hardware = 7;
  for (std::size_t i = 0; i < 16; ++i) info.serial[i] = static_cast<std::uint8_t>(0xF0 + i);
  test::append(s, encode_descriptor(AnswerType::kDevInfo));
  test::append(s, encode_device_info(info));
  s.push_back(0x33);  // junk between answers
  test::append(s, encode_descriptor(AnswerType::kHealth));
  test::append(s, encode_health({2, 0x8001}));
  test::append(s, encode_descriptor(AnswerType::kSampleRate));
  test::append(s, encode_sample_rate({476, 238}));
  // LIDAR_CONF SCAN_MODE_TYPICAL -> u16 2, and SCAN_MODE_NAME -> "Sensitivity".
  test::append(s, encode_descriptor(AnswerType::kLidarConf, 6, SendMode::kSingle));
  test::append(s, Bytes{0x7C, 0, 0, 0, 2, 0});
  const std::string name = "Sensitivity";
  test::append(
      s, encode_descriptor(AnswerType::kLidarConf, static_cast<std::uint32_t>(4 + name.size() + 1),
                           SendMode::kSingle));
  test::append(s, Bytes{0x7F, 0, 0, 0});
  test::append(s, Bytes(name.begin(), name.end()));
  s.push_back(0);
  test::append(s, encode_descriptor(AnswerType::kAccBoardFlag));
  test::append(s, Bytes{1, 0, 0, 0});
  return s;
}

TEST(RplidarCodec, SingleAnswers) {
  Decoder d;
  d.expect_any();
  const auto got = test::decode_all(d, single_answers());
  ASSERT_EQ(got.messages.size(), 6U);
  ASSERT_EQ(got.messages[0].kind, MessageKind::kDeviceInfo);
  const DeviceInfo& info = got.messages[0].device_info;
  EXPECT_EQ(info.model, 0x18);
  EXPECT_EQ(info.firmware(), 0x011D);
  EXPECT_EQ(info.hardware, 7);
  EXPECT_EQ(info.serial[15], 0xFF);
  ASSERT_EQ(got.messages[1].kind, MessageKind::kHealth);
  EXPECT_EQ(got.messages[1].health.status, 2);
  EXPECT_EQ(got.messages[1].health.error_code, 0x8001);
  EXPECT_TRUE(got.messages[1].health.is_error());
  ASSERT_EQ(got.messages[2].kind, MessageKind::kSampleRate);
  EXPECT_EQ(got.messages[2].sample_rate, (SampleRate{476, 238}));
  ASSERT_EQ(got.messages[3].kind, MessageKind::kLidarConf);
  EXPECT_EQ(got.messages[3].lidar_conf.type, 0x7CU);
  EXPECT_EQ(got.messages[3].lidar_conf.as_uint(2), 2U);
  ASSERT_EQ(got.messages[4].kind, MessageKind::kLidarConf);
  EXPECT_EQ(got.messages[4].lidar_conf.as_text(), "Sensitivity");
  ASSERT_EQ(got.messages[5].kind, MessageKind::kAccBoardFlag);
  EXPECT_TRUE(got.messages[5].acc_board.pwm_supported());
  EXPECT_EQ(d.stats().codec.bytes_skipped, 1U);
  EXPECT_FALSE(d.stream_type().has_value());
}

TEST(RplidarCodec, UnexpectedAnswerIsSkipped) {
  Bytes s;
  test::append(s, encode_descriptor(AnswerType::kHealth));
  test::append(s, encode_health({0, 0}));
  test::append(s, encode_descriptor(AnswerType::kSampleRate));
  test::append(s, encode_sample_rate({500, 250}));
  Decoder d;
  d.expect(AnswerType::kSampleRate);
  const auto got = test::decode_all(d, s);
  ASSERT_EQ(got.messages.size(), 1U);
  EXPECT_EQ(got.messages[0].kind, MessageKind::kSampleRate);
  EXPECT_EQ(d.stats().unexpected_answers, 1U);
}

TEST(RplidarCodec, MalformedAndUnsupportedDescriptors) {
  Bytes s;
  test::append(s, encode_descriptor(AnswerType::kHealth, 9, SendMode::kSingle));       // wrong size
  test::append(s, encode_descriptor(AnswerType::kMeasurement, 5, SendMode::kSingle));  // mode
  test::append(s, encode_descriptor(AnswerType::kHqCapsule, 781, SendMode::kContinuous));
  test::append(s, encode_descriptor(AnswerType::kHealth));
  test::append(s, encode_health({1, 7}));
  Decoder d;
  const auto got = test::decode_all(d, s);
  ASSERT_EQ(got.messages.size(), 1U);
  EXPECT_EQ(got.messages[0].health.status, 1);
  EXPECT_EQ(d.stats().codec.framing_errors, 2U);
  EXPECT_EQ(d.stats().codec.unsupported, 1U);
}

TEST(RplidarCodec, SplitAtEveryByteBoundaryGivesIdenticalOutput) {
  Bytes s = single_answers();
  auto nodes = make_nodes(25);
  Bytes stream = node_stream(nodes);
  stream[kDescriptorSize + 5 * kNodeSize + 1] &= 0xFE;  // one bad node in the middle
  test::append(s, stream);
  Decoder whole_decoder;
  const auto whole = test::decode_all(whole_decoder, s);
  ASSERT_GT(whole.nodes.size(), 20U);
  for (std::size_t cut = 1; cut < s.size(); ++cut) {
    Decoder d;
    test::Collected got;
    test::decode_into(d, std::span(s).first(cut), got);
    test::decode_into(d, std::span(s).subspan(cut), got);
    ASSERT_EQ(got.messages.size(), whole.messages.size()) << cut;
    ASSERT_EQ(got.nodes, whole.nodes) << cut;
    ASSERT_EQ(d.stats().codec.bytes_skipped, whole_decoder.stats().codec.bytes_skipped) << cut;
  }
}

TEST(RplidarCodec, ResetLeavesStreamMode) {
  Decoder d;
  d.expect(AnswerType::kMeasurement);
  (void)test::decode_all(d, node_stream(make_nodes(3)));
  EXPECT_TRUE(d.stream_type().has_value());
  d.expect(AnswerType::kHealth);  // after STOP + GET_HEALTH
  EXPECT_FALSE(d.stream_type().has_value());
  Bytes s = {0x3E, 0x01};  // tail of a node still in flight
  test::append(s, encode_descriptor(AnswerType::kHealth));
  test::append(s, encode_health({0, 0}));
  const auto got = test::decode_all(d, s);
  ASSERT_EQ(got.messages.size(), 1U);
  EXPECT_EQ(got.messages[0].kind, MessageKind::kHealth);
}

// ---- capsules -------------------------------------------------------------------------------

std::array<std::uint16_t, 40> dense_distances(std::uint16_t base) {
  std::array<std::uint16_t, 40> d{};
  for (std::size_t k = 0; k < 40; ++k) d[k] = static_cast<std::uint16_t>(base + k);
  d[7] = 0;  // one invalid sample
  return d;
}

TEST(RplidarCodec, DenseCapsulesInterpolateAnglesAndNeedTheNextCapsule) {
  Bytes s;
  test::append(s, encode_descriptor(AnswerType::kDenseCapsule));
  // Start angles 340, 350, 0, 10 deg (q6): the second pair crosses 360.
  const std::array<std::uint16_t, 4> starts = {340 * 64, 350 * 64, 0, 10 * 64};
  for (std::size_t i = 0; i < starts.size(); ++i) {
    const auto dist = dense_distances(static_cast<std::uint16_t>(1000 * (i + 1)));
    test::append(s, encode_dense_capsule(starts[i], i == 0, dist));
  }
  Decoder d;
  d.expect(AnswerType::kDenseCapsule);
  const auto got = test::decode_all(d, s);
  ASSERT_EQ(got.messages.size(), 3U);
  ASSERT_EQ(got.nodes.size(), 120U);
  for (std::size_t i = 0; i < 3; ++i) {
    for (std::size_t k = 0; k < 40; ++k) {
      const HqNode& n = got.nodes[i * 40 + k];
      const double want_deg =
          std::fmod(340.0 + 10.0 * static_cast<double>(i) + 0.25 * static_cast<double>(k), 360.0);
      // angle_q6 = want*64 exactly; z_q14 = q6*256/90 truncated.
      EXPECT_EQ(n.angle_z_q14, static_cast<std::uint16_t>(
                                   (static_cast<int>(std::lround(want_deg * 64)) * 256) / 90))
          << i << "," << k;
      const std::uint32_t want_mm = k == 7 ? 0 : static_cast<std::uint32_t>(1000 * (i + 1) + k);
      EXPECT_EQ(n.dist_mm_q2, want_mm * 4);
      EXPECT_EQ(n.quality, want_mm != 0 ? 188 : 0);
    }
  }
  // Exactly one new-scan flag, on the sample whose next step crosses 360 deg (i = 1, k = 39).
  std::size_t flags = 0;
  for (std::size_t j = 0; j < got.nodes.size(); ++j) {
    if (got.nodes[j].start_of_scan()) {
      ++flags;
      EXPECT_EQ(j, 79U);
    }
  }
  EXPECT_EQ(flags, 1U);
  EXPECT_EQ(d.stats().capsule_restarts, 1U);
}

TEST(RplidarCodec, DenseChecksumErrorAndRestartResetTheCapsulePair) {
  Bytes s;
  test::append(s, encode_descriptor(AnswerType::kDenseCapsule));
  for (std::uint16_t i = 0; i < 6; ++i) {
    auto c = encode_dense_capsule(static_cast<std::uint16_t>(i * 640), false, dense_distances(500));
    if (i == 2) c[10] ^= 0x40;  // corrupt: checksum fails
    test::append(s, c);
  }
  Decoder d;
  d.expect(AnswerType::kDenseCapsule);
  const auto got = test::decode_all(d, s);
  // Pairs (0,1) decoded; capsule 2 bad -> 1 has no successor, 3 has no predecessor;
  // pairs (3,4), (4,5) decoded.
  EXPECT_EQ(got.messages.size(), 3U);
  EXPECT_EQ(d.stats().codec.checksum_errors, 1U);
}

TEST(RplidarCodec, DenseAngleStepCheck) {
  Bytes s;
  test::append(s, encode_descriptor(AnswerType::kDenseCapsule));
  test::append(s, encode_dense_capsule(0, false, dense_distances(500)));
  test::append(s, encode_dense_capsule(200 * 64, false, dense_distances(500)));  // 200 deg step
  DecoderConfig cfg;
  cfg.dense_sample_duration_us = 31;  // 32 kSa/s: at most 44.6 deg per capsule at 100 Hz
  Decoder d(cfg);
  d.expect(AnswerType::kDenseCapsule);
  const auto got = test::decode_all(d, s);
  EXPECT_TRUE(got.messages.empty());
  EXPECT_EQ(d.stats().dense_rejected, 1U);
}

// Express legacy capsule built by hand: every sample's angle follows
// theta_j = w_i + j * diff / 32 - dtheta_j / 8 (docs/protocols.md 1.7).
TEST(RplidarCodec, HandBuiltExpressCapsules) {
  auto make = [](std::uint16_t start_q6, std::uint16_t dist_mm) {
    std::array<std::uint8_t, kCapsuleSize> c{};
    c[2] = static_cast<std::uint8_t>(start_q6 & 0xFF);
    c[3] = static_cast<std::uint8_t>(start_q6 >> 8);
    for (std::size_t k = 0; k < 16; ++k) {
      // dtheta_A = 40 (5 deg) = 0b101000: low nibble 8, high bits 2; dtheta_B = 8 (1 deg).
      const auto d1 = static_cast<std::uint16_t>(((dist_mm + k) << 2) | 2);
      const auto d2 = static_cast<std::uint16_t>(((dist_mm + k) << 2) | 0);
      std::uint8_t* p = c.data() + 4 + 5 * k;
      p[0] = static_cast<std::uint8_t>(d1 & 0xFF);
      p[1] = static_cast<std::uint8_t>(d1 >> 8);
      p[2] = static_cast<std::uint8_t>(d2 & 0xFF);
      p[3] = static_cast<std::uint8_t>(d2 >> 8);
      p[4] = static_cast<std::uint8_t>(0x08 | (0x08 << 4));
    }
    seal_capsule(c);
    return c;
  };
  Bytes s;
  test::append(s, encode_descriptor(AnswerType::kCapsule));
  test::append(s, make(100 * 64, 2000));
  test::append(s, make(116 * 64, 3000));  // 16 deg later: 0.5 deg per sample
  Decoder d;
  d.expect(AnswerType::kCapsule);
  const auto got = test::decode_all(d, s);
  ASSERT_EQ(got.nodes.size(), 32U);
  for (std::size_t j = 0; j < 32; ++j) {
    const double dtheta = (j % 2 == 0) ? 5.0 : 1.0;
    const double want = 100.0 + 0.5 * static_cast<double>(j) - dtheta;
    EXPECT_NEAR(got.nodes[j].angle_deg(), want, 0.02) << j;
    EXPECT_EQ(got.nodes[j].dist_mm_q2, (2000 + j / 2) * 4U) << j;
    EXPECT_EQ(got.nodes[j].flag, 2);
  }
}

TEST(RplidarCodec, CapsuleStreamResyncsAfterJunk) {
  Bytes s;
  test::append(s, encode_descriptor(AnswerType::kDenseCapsule));
  for (std::uint16_t i = 0; i < 8; ++i) {
    test::append(
        s, encode_dense_capsule(static_cast<std::uint16_t>(i * 640), false, dense_distances(800)));
    if (i == 3) test::append(s, Bytes{0x12, 0xA7, 0x00, 0x99});  // junk between capsules
  }
  Decoder d;
  d.expect(AnswerType::kDenseCapsule);
  const auto got = test::decode_all(d, s);
  // Pairs (0,1),(1,2),(2,3) then sync is lost; (4,5),(5,6),(6,7) after it.
  EXPECT_EQ(got.messages.size(), 6U);
  EXPECT_EQ(d.stats().capsule_sync_errors, 1U);
  EXPECT_EQ(d.stats().codec.bytes_skipped, 4U);
  EXPECT_EQ(d.stats().codec.checksum_errors, 0U);
}

// Ultra capsule built by hand: majors below 512 (level 0), predictions 0 -> all three samples of
// a cabin at the major's distance; the last cabin borrows cabin 0 of the next capsule.
TEST(RplidarCodec, HandBuiltUltraCapsules) {
  auto make = [](std::uint16_t start_q6, std::uint32_t major_mm, std::uint32_t predict1) {
    std::array<std::uint8_t, kUltraCapsuleSize> c{};
    c[2] = static_cast<std::uint8_t>(start_q6 & 0xFF);
    c[3] = static_cast<std::uint8_t>(start_q6 >> 8);
    for (std::size_t k = 0; k < 32; ++k) {
      const std::uint32_t w = (major_mm & 0xFFF) | ((predict1 & 0x3FF) << 12) | (0U << 22);
      for (std::size_t b = 0; b < 4; ++b)
        c[4 + 4 * k + b] = static_cast<std::uint8_t>(w >> (8 * b));
    }
    seal_capsule(c);
    return c;
  };
  Bytes s;
  test::append(s, encode_descriptor(AnswerType::kUltraCapsule));
  test::append(s, make(0, 300, 0x3FF));        // predict1 = -1
  test::append(s, make(24 * 64, 400, 0x1FF));  // predict1 = +511 = invalid marker
  test::append(s, make(48 * 64, 400, 0));
  Decoder d;
  d.expect(AnswerType::kUltraCapsule);
  const auto got = test::decode_all(d, s);
  ASSERT_EQ(got.nodes.size(), 192U);
  for (std::size_t j = 0; j < 96; ++j) {
    const std::uint32_t want_mm = j % 3 == 0 ? 300 : (j % 3 == 1 ? 299 : (j == 95 ? 400 : 300));
    EXPECT_EQ(got.nodes[j].dist_mm_q2, want_mm * 4) << j;
    // Angle: 0.25 deg per sample minus the 8 deg - k2 correction (about 5.6 deg at 300 mm).
    const double k2 = std::floor(98361.0 / (4.0 * want_mm));
    const double corr =
        (8.0 * 3.1415926535 / 180.0 - k2 * 64 / 65536.0 - k2 * k2 * k2 / 98304.0 / 65536.0) *
        180.0 / 3.1415926535;
    const double want = std::fmod(0.25 * static_cast<double>(j) - corr + 360.0, 360.0);
    EXPECT_NEAR(got.nodes[j].angle_deg(), want, 0.03) << j;
  }
  for (std::size_t j = 96; j < 192; ++j) {
    if (j % 3 == 1) {
      EXPECT_EQ(got.nodes[j].dist_mm_q2, 0U) << j;
      EXPECT_EQ(got.nodes[j].quality, 0) << j;
    }
  }
}

TEST(RplidarModel, TableFromDevInfo) {
  auto info = [](std::uint8_t model, std::uint8_t hw, std::uint16_t fw) {
    DeviceInfo d;
    d.model = model;
    d.hardware = hw;
    d.firmware_major = static_cast<std::uint8_t>(fw >> 8);
    d.firmware_minor = static_cast<std::uint8_t>(fw & 0xFF);
    return d;
  };
  const ModelInfo a1 = model_info(info(0x18, 7, 0x011D));
  EXPECT_EQ(a1.family, Family::kA);
  EXPECT_EQ(a1.name_view(), "A1M8");
  EXPECT_EQ(a1.native_baud, 115200U);
  EXPECT_EQ(a1.motor, MotorControl::kDtr);
  EXPECT_FALSE(a1.query_acc_board);
  EXPECT_TRUE(a1.supports_conf);
  EXPECT_FLOAT_EQ(a1.max_range_m, 12.0F);
  const ModelInfo a1_old = model_info(info(0x18, 5, 0x0110));
  EXPECT_FALSE(a1_old.supports_conf);
  EXPECT_FALSE(a1_old.supports_sample_rate);
  const ModelInfo a2m8 = model_info(info(0x28, 5, 0x011A));
  EXPECT_EQ(a2m8.name_view(), "A2M8");
  EXPECT_EQ(a2m8.native_baud, 115200U);
  EXPECT_EQ(a2m8.motor, MotorControl::kPwm);
  EXPECT_TRUE(a2m8.query_acc_board);
  const ModelInfo a2m12 = model_info(info(0x2C, 6, 0x011A));
  EXPECT_EQ(a2m12.name_view(), "A2M12");
  EXPECT_EQ(a2m12.native_baud, 256000U);
  const ModelInfo a3 = model_info(info(0x31, 6, 0x011A));
  EXPECT_EQ(a3.native_baud, 256000U);
  EXPECT_FLOAT_EQ(a3.max_range_m, 25.0F);
  const ModelInfo c1 = model_info(info(0x41, 1, 0x0101));
  EXPECT_EQ(c1.family, Family::kC);
  EXPECT_EQ(c1.name_view(), "C1M1");
  EXPECT_EQ(c1.native_baud, 460800U);
  EXPECT_TRUE(c1.supports_conf);
  const ModelInfo s1 = model_info(info(0x61, 1, 0x0101));
  EXPECT_EQ(s1.name_view(), "S1M1");
  EXPECT_EQ(s1.native_baud, 256000U);
  EXPECT_EQ(s1.motor, MotorControl::kRpmCommand);
  EXPECT_EQ(model_info(info(0x71, 1, 0x0101)).native_baud, 1000000U);
  EXPECT_EQ(model_info(info(0x82, 1, 0x0101)).native_baud, 460800U);
  EXPECT_EQ(model_info(info(0x81, 1, 0x0101)).native_baud, 1000000U);
  EXPECT_EQ(model_info(info(0x00, 0, 0)).family, Family::kUnknown);
}

}  // namespace
}  // namespace coxswain::drivers::rplidar
