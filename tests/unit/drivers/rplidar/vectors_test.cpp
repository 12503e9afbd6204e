// SPDX-License-Identifier: Apache-2.0
// Bit-exact agreement with the recorded pyrplidar capsule vectors (docs/protocols.md 1.7-1.8,
// testdata/rplidar/pyrplidar_capsule_vectors.json). Skips when the shared test data is absent.
#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "coxswain/drivers/rplidar/answer_encoder.hpp"
#include "coxswain/drivers/rplidar/codec.hpp"
#include "decode_helpers.hpp"
#include "support/testdata.hpp"

namespace coxswain::drivers::rplidar {
namespace {

std::vector<std::uint8_t> from_hex(const std::string& hex) {
  std::vector<std::uint8_t> out;
  for (std::size_t i = 0; i + 1 < hex.size(); i += 2) {
    out.push_back(static_cast<std::uint8_t>(std::stoul(hex.substr(i, 2), nullptr, 16)));
  }
  return out;
}

nlohmann::json load(const std::filesystem::path& p) {
  std::ifstream in(p);
  return nlohmann::json::parse(in);
}

// Feeds descriptor + capsules (whole, then one byte at a time) and checks every expected node.
void check_capsules(const nlohmann::json& section, AnswerType type) {
  std::vector<std::uint8_t> stream;
  test::append(stream, encode_descriptor(type));
  std::size_t capsules = 0;
  for (const auto& hex : section["capsules_hex"]) {
    test::append(stream, from_hex(hex.get<std::string>()));
    ++capsules;
  }
  std::vector<HqNode> expected;
  std::size_t batches = 0;
  for (const auto& batch : section["expected_nodes"]) {
    ++batches;
    for (const auto& t : batch) {
      HqNode n;
      n.flag = t[0].get<std::uint8_t>();
      n.quality = t[1].get<std::uint8_t>();
      n.angle_z_q14 = t[2].get<std::uint16_t>();
      n.dist_mm_q2 = t[3].get<std::uint32_t>();
      expected.push_back(n);
    }
  }
  ASSERT_EQ(batches + 1, capsules);

  for (const bool bytewise : {false, true}) {
    SCOPED_TRACE(bytewise ? "one byte at a time" : "whole stream");
    Decoder d;
    d.expect(type);
    test::Collected got;
    if (bytewise) {
      for (const std::uint8_t b : stream) test::decode_into(d, std::span(&b, 1), got);
    } else {
      got = test::decode_all(d, stream);
    }
    ASSERT_EQ(got.messages.size(), batches);
    ASSERT_EQ(got.nodes.size(), expected.size());
    std::size_t mismatches = 0;
    for (std::size_t i = 0; i < expected.size(); ++i) {
      if (got.nodes[i] == expected[i]) continue;
      if (++mismatches <= 5) {
        ADD_FAILURE() << "node " << i << ": got flag " << int{got.nodes[i].flag} << " q "
                      << int{got.nodes[i].quality} << " z " << got.nodes[i].angle_z_q14 << " d "
                      << got.nodes[i].dist_mm_q2 << ", want flag " << int{expected[i].flag} << " q "
                      << int{expected[i].quality} << " z " << expected[i].angle_z_q14 << " d "
                      << expected[i].dist_mm_q2;
      }
    }
    EXPECT_EQ(mismatches, 0U);
    EXPECT_EQ(d.stats().codec.checksum_errors, 0U);
    EXPECT_EQ(d.stats().codec.frames_ok, capsules);
    EXPECT_EQ(d.stats().codec.bytes_skipped, 0U);
  }
}

TEST(RplidarVectors, ExpressCapsulesBitExact) {
  COXSWAIN_REQUIRE_TESTDATA(path, "rplidar/pyrplidar_capsule_vectors.json");
  const auto j = load(path);
  check_capsules(j["express_capsules_ans_type_0x82"], AnswerType::kCapsule);
}

TEST(RplidarVectors, UltraCapsulesBitExact) {
  COXSWAIN_REQUIRE_TESTDATA(path, "rplidar/pyrplidar_capsule_vectors.json");
  const auto j = load(path);
  check_capsules(j["ultra_capsules_ans_type_0x84"], AnswerType::kUltraCapsule);
}

TEST(RplidarVectors, VarBitScale) {
  COXSWAIN_REQUIRE_TESTDATA(path, "rplidar/pyrplidar_capsule_vectors.json");
  const auto j = load(path)["varbitscale_decode"];
  ASSERT_EQ(j["input"].size(), j["output_value"].size());
  for (std::size_t i = 0; i < j["input"].size(); ++i) {
    const VarBitScale v = varbitscale_decode(j["input"][i].get<std::uint32_t>());
    EXPECT_EQ(v.value_mm, j["output_value"][i].get<std::uint32_t>()) << i;
    EXPECT_EQ(v.level, j["output_scale_level"][i].get<std::uint32_t>()) << i;
  }
}

TEST(RplidarVectors, DescriptorExamples) {
  COXSWAIN_REQUIRE_TESTDATA(path, "rplidar/pyrplidar_capsule_vectors.json");
  const auto vectors = load(path);  // range-for would not keep a temporary's member alive
  for (const auto& e : vectors["response_descriptor_examples"]) {
    const auto bytes = from_hex(e["hex"].get<std::string>());
    const auto type =
        static_cast<AnswerType>(std::stoul(e["data_type"].get<std::string>(), nullptr, 16));
    const auto mode = e["send_mode"].get<int>() == 1 ? SendMode::kContinuous : SendMode::kSingle;
    const auto ours = encode_descriptor(type, e["data_length"].get<std::uint32_t>(), mode);
    EXPECT_EQ(std::vector<std::uint8_t>(ours.begin(), ours.end()), bytes);
    Decoder d;
    (void)test::decode_all(d, bytes);
    EXPECT_EQ(d.stats().descriptors, 1U);
    EXPECT_EQ(d.stream_type().has_value(), mode == SendMode::kContinuous);
  }
}

// Hand-built ultra/varbitscale cases that always run (table of docs/protocols.md 1.8).
TEST(RplidarVectors, VarBitScaleTableEdges) {
  EXPECT_EQ(varbitscale_decode(0).value_mm, 0U);
  EXPECT_EQ(varbitscale_decode(511).value_mm, 511U);
  EXPECT_EQ(varbitscale_decode(512).value_mm, 512U);
  EXPECT_EQ(varbitscale_decode(513).value_mm, 514U);
  EXPECT_EQ(varbitscale_decode(1280).value_mm, 2048U);
  EXPECT_EQ(varbitscale_decode(1792).value_mm, 4096U);
  EXPECT_EQ(varbitscale_decode(3328).value_mm, 16384U);
  EXPECT_EQ(varbitscale_decode(4095).value_mm, 16384U + 767U * 16U);
  EXPECT_EQ(varbitscale_decode(4095).level, 4U);
}

}  // namespace
}  // namespace coxswain::drivers::rplidar
