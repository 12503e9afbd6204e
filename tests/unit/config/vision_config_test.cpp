// SPDX-License-Identifier: Apache-2.0
// The vision file: the shipped one is the built-in model, what write_vision emits reads back
// unchanged, and mistakes are reported with their key.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "coxswain/config/vision_config.hpp"
#include "support/testdata.hpp"

namespace coxswain::config {
namespace {

using perception::VisionParams;

void expect_same(const VisionParams& a, const VisionParams& b) {
  ASSERT_EQ(a.colour_count, b.colour_count);
  for (std::size_t i = 0; i < a.colour_count; ++i) {
    EXPECT_EQ(a.colours[i].colour, b.colours[i].colour);
    EXPECT_EQ(a.colours[i].hsv.h_min, b.colours[i].hsv.h_min);
    EXPECT_EQ(a.colours[i].hsv.h_max, b.colours[i].hsv.h_max);
    EXPECT_EQ(a.colours[i].hsv.s_min, b.colours[i].hsv.s_min);
    EXPECT_EQ(a.colours[i].hsv.v_min, b.colours[i].hsv.v_min);
    EXPECT_EQ(a.colours[i].hsv.v_max, b.colours[i].hsv.v_max);
    EXPECT_EQ(a.colours[i].markers, b.colours[i].markers);
    EXPECT_EQ(a.colours[i].buoys, b.colours[i].buoys);
  }
  EXPECT_EQ(a.blur_kernel_px, b.blur_kernel_px);
  EXPECT_EQ(a.close_kernel_px, b.close_kernel_px);
  EXPECT_DOUBLE_EQ(a.min_area_fraction, b.min_area_fraction);
  EXPECT_EQ(a.background.strips, b.background.strips);
  EXPECT_EQ(a.background.sample_step_px, b.background.sample_step_px);
  EXPECT_EQ(a.background.max_samples, b.background.max_samples);
  EXPECT_DOUBLE_EQ(a.background.reject_sigma, b.background.reject_sigma);
  EXPECT_EQ(a.background.max_saturation, b.background.max_saturation);
  EXPECT_DOUBLE_EQ(a.shape.island_min_hole_fraction, b.shape.island_min_hole_fraction);
}

std::string temp_file(const std::string& name, const std::string& text) {
  const std::filesystem::path p = std::filesystem::temp_directory_path() / name;
  std::ofstream(p) << text;
  return p.string();
}

TEST(VisionConfig, ShippedFileIsTheBuiltInModel) {
  ConfigErrors errors;
  const auto p =
      load_vision_file((testing::source_dir() / "config" / "vision.yaml").string(), errors);
  ASSERT_TRUE(p.has_value()) << errors.format();
  expect_same(*p, VisionParams::defaults());
}

TEST(VisionConfig, WrittenFileReadsBackUnchanged) {
  VisionParams v = VisionParams::defaults();
  v.colours[4].hsv.h_min = 105;  // a venue's blue
  v.background.reject_sigma = 3.5;
  v.shape.island_min_hole_fraction = 0.2;
  std::ostringstream out;
  write_vision(v, out);
  ConfigErrors errors;
  const auto back = load_vision_file(temp_file("coxswain_vision_rt.yaml", out.str()), errors);
  ASSERT_TRUE(back.has_value()) << errors.format();
  expect_same(*back, v);
}

TEST(VisionConfig, WrittenNumbersReadBackBitForBit) {
  // A venue's tuning with more digits than a default stream prints (6) must survive a save.
  VisionParams v = VisionParams::defaults();
  v.min_area_fraction = 0.000412345678912;
  v.background.reject_sigma = 4.123456789;
  v.shape.cross_min_defect_depth = 0.1234567891;
  std::ostringstream out;
  write_vision(v, out);
  ConfigErrors errors;
  const auto back = load_vision_file(temp_file("coxswain_vision_bits.yaml", out.str()), errors);
  ASSERT_TRUE(back.has_value()) << errors.format();
  EXPECT_EQ(back->min_area_fraction, v.min_area_fraction);
  EXPECT_EQ(back->background.reject_sigma, v.background.reject_sigma);
  EXPECT_EQ(back->shape.cross_min_defect_depth, v.shape.cross_min_defect_depth);
}

TEST(VisionConfig, UnknownKeyAndBadValuesAreErrorsWithTheirKey) {
  ConfigErrors errors;
  const auto p = load_vision_file(temp_file("coxswain_vision_bad.yaml",
                                            "kind: vision\n"
                                            "colours:\n"
                                            "  - {colour: teal, h_min: 200}\n"
                                            "background: {rejct_sigma: 2}\n"),
                                  errors);
  EXPECT_FALSE(p.has_value());
  const std::string text = errors.format();
  EXPECT_NE(text.find("colour"), std::string::npos) << text;
  EXPECT_NE(text.find("h_min"), std::string::npos) << text;
  EXPECT_NE(text.find("rejct_sigma"), std::string::npos) << text;
}

TEST(VisionConfig, InvalidModelIsRefused) {
  ConfigErrors errors;
  const auto p = load_vision_file(
      temp_file("coxswain_vision_invalid.yaml", "kind: vision\nbackground: {strips: 40}\n"),
      errors);
  EXPECT_FALSE(p.has_value());
  EXPECT_NE(errors.format().find("strips"), std::string::npos) << errors.format();
}

}  // namespace
}  // namespace coxswain::config
