// SPDX-License-Identifier: Apache-2.0
// Marker detection on the shared images of the shared test data folder/markers, judged against
// labels.csv. Skips when the shared folder is absent. Every clean synthetic signdet_* image and the
// simulator render must be exactly right; the real photo and the SUAS pages are measured and
// reported.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "coxswain/perception/marker_detector.hpp"
#include "support/testdata.hpp"

namespace coxswain::perception {
namespace {

using msg::Colour;
using msg::Shape;

struct Expected {
  Colour colour = Colour::kUnknown;  // kUnknown: a colour we do not search (cyan)
  Shape shape = Shape::kUnknown;     // kUnknown: a distractor (pentagon, star, semicircle...)
};

Shape parse_shape(const std::string& s) {
  if (s == "triangle") return Shape::kTriangle;
  if (s == "square" || s == "rectangle") return Shape::kRectangle;
  if (s == "cross") return Shape::kCross;
  if (s == "circle") return Shape::kCircle;
  return Shape::kUnknown;
}

Colour parse_colour(const std::string& s) {
  for (const Colour c : {Colour::kRed, Colour::kGreen, Colour::kBlue, Colour::kYellow,
                         Colour::kOrange, Colour::kPurple, Colour::kBlack, Colour::kWhite}) {
    if (s == colour_name(c)) return c;
  }
  return Colour::kUnknown;
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, sep)) out.push_back(item);
  return out;
}

TEST(MarkerTestdata, LabelsCsv) {
  COXSWAIN_REQUIRE_TESTDATA(labels, "markers/labels.csv");
  std::ifstream in(labels);
  ASSERT_TRUE(in.good());
  std::string line;
  std::getline(in, line);  // header
  MarkerDetector det;
  msg::CameraDetections out;
  int targets = 0;
  int found = 0;
  int false_positives = 0;
  int images = 0;
  int images_right = 0;
  std::ostringstream report;
  while (std::getline(in, line)) {
    const std::vector<std::string> f = split(line, ',');
    if (f.size() < 5) continue;
    const std::string& file = f[0];
    const std::string& kind = f[1];
    std::vector<Expected> expected;
    for (const std::string& obj : split(f[4], ';')) {
      const std::vector<std::string> sc = split(obj, ':');
      if (sc.size() == 2) expected.push_back({parse_colour(sc[1]), parse_shape(sc[0])});
    }
    const cv::Mat img = cv::imread((labels.parent_path() / file).string(), cv::IMREAD_COLOR);
    ASSERT_FALSE(img.empty()) << file;
    ASSERT_TRUE(det.detect(img, 0, out));
    EXPECT_EQ(out.image_width_px, std::stoi(f[2])) << file;
    ++images;

    // Each labelled marker found with the right colour and shape; left-to-right order kept.
    int image_targets = 0;
    int image_found = 0;
    std::vector<float> xs;
    for (const Expected& e : expected) {
      if (e.shape == Shape::kUnknown || e.colour == Colour::kUnknown) continue;
      ++image_targets;
      const auto hit = find_target(out, e.colour, e.shape);
      if (hit) {
        ++image_found;
        xs.push_back(hit->center_x_px);
      }
    }
    const bool ordered = std::is_sorted(xs.begin(), xs.end());
    // Anything reported that is not labelled is a false positive.
    int image_fp = 0;
    std::ostringstream got;
    for (std::uint32_t i = 0; i < out.count; ++i) {
      const msg::Detection& d = out.detections[i];
      got << " " << colour_name(d.colour) << "/" << shape_name(d.shape);
      const bool labelled = std::any_of(expected.begin(), expected.end(), [&](const Expected& e) {
        return e.colour == d.colour && e.shape == d.shape;
      });
      if (!labelled) ++image_fp;
    }
    targets += image_targets;
    found += image_found;
    false_positives += image_fp;
    const bool right = image_found == image_targets && image_fp == 0 && ordered;
    if (right) ++images_right;
    report << "  " << (right ? "ok  " : "FAIL") << " " << file << " (" << kind << "): found "
           << image_found << "/" << image_targets << ", false positives " << image_fp
           << ", got:" << got.str() << "\n";

    const bool clean_synthetic = file.rfind("signdet_", 0) == 0 && kind == "synthetic_template";
    const bool sim = kind == "sim_render" || kind == "sim_render_crop";
    if (clean_synthetic || sim) {
      EXPECT_TRUE(right) << file << ": found " << image_found << "/" << image_targets
                         << ", false positives " << image_fp << ", got:" << got.str();
    }
  }
  std::cout << "[ markers ] " << images_right << "/" << images << " images fully right; labelled "
            << "markers found " << found << "/" << targets << "; false positives "
            << false_positives << "\n"
            << report.str();
  EXPECT_GT(images, 20);
}

}  // namespace
}  // namespace coxswain::perception
