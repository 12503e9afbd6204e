// SPDX-License-Identifier: Apache-2.0
// Marker detection on the shared images of the shared test data folder/markers, judged against
// labels.csv. Skips when the shared folder is absent. Every clean synthetic signdet_* image and the
// simulator render must be exactly right; the real photo's misses are explained (and the
// explanation checked) in a test of their own; the SUAS pages are measured and reported.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
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

/// The `q` quantile (0..1) of channel `channel` of `hsv` over `box`.
int channel_quantile(const cv::Mat& hsv, const cv::Rect& box, int channel, double q) {
  std::vector<int> v;
  for (int y = box.y; y < box.y + box.height; ++y) {
    for (int x = box.x; x < box.x + box.width; ++x) v.push_back(hsv.at<cv::Vec3b>(y, x)[channel]);
  }
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1))];
}

// The one real photo (a 2015 RobotX-style dock mock-up, 554 x 238 px): its three "black" glyphs
// (cross, triangle, circle, left to right) are not found, and a green cross is reported on the
// bank. Each is explained here, and the explanation is checked on the pixels, so the test fails
// if a miss happens for another reason:
//  - haze and exposure left every glyph a pale lavender grey: even its darkest pixels (value
//    167-183 of 255) are over twice the black box's limit (75) and two thirds as bright as the
//    placard round them, and too grey (saturation under 60) for any colour box. No colour box for
//    black can take them without taking the placards' own shade and every shadow; finding them
//    would need black judged against its placard;
//  - the green cross is a tuft of the grass bank beyond the dock's last post, on no placard.
TEST(MarkerTestdata, TheRealPhotosMissesAreTooPaleForBlack) {
  COXSWAIN_REQUIRE_TESTDATA(photo, "markers/signdet_dock.jpg");
  const cv::Mat img = cv::imread(photo.string(), cv::IMREAD_COLOR);
  ASSERT_FALSE(img.empty());
  const VisionParams params = VisionParams::defaults();
  const int black = params.find_colour(Colour::kBlack);
  ASSERT_GE(black, 0);
  const int black_v_max = params.colours[static_cast<std::size_t>(black)].hsv.v_max;
  MarkerDetector det(params);
  msg::CameraDetections out;
  ASSERT_TRUE(det.detect(img, 0, out));
  cv::Mat hsv;
  cv::cvtColor(img, hsv, cv::COLOR_BGR2HSV);
  // The three placards, each holding its whole glyph (read off the photo).
  const std::array<cv::Rect, 3> placards{cv::Rect(82, 112, 56, 44), cv::Rect(226, 116, 56, 44),
                                         cv::Rect(380, 116, 56, 48)};
  const std::array<Shape, 3> shapes{Shape::kCross, Shape::kTriangle, Shape::kCircle};
  for (std::size_t i = 0; i < placards.size(); ++i) {
    const cv::Rect& p = placards[i];
    const bool found = std::any_of(
        out.detections.begin(), out.detections.begin() + out.count, [&](const msg::Detection& d) {
          return d.colour == Colour::kBlack && d.shape == shapes[i] &&
                 p.contains(
                     cv::Point(static_cast<int>(d.center_x_px), static_cast<int>(d.center_y_px)));
        });
    if (found) continue;  // nothing to explain
    const int glyph_v = channel_quantile(hsv, p, 2, 0.05);
    const int placard_v = channel_quantile(hsv, p, 2, 0.90);
    const int glyph_s = channel_quantile(hsv, p, 1, 0.95);
    std::cout << "[ photo ] " << shape_name(shapes[i]) << " placard: darkest glyph value "
              << glyph_v << " (black box up to " << black_v_max << "), placard " << placard_v
              << ", saturation up to " << glyph_s << "\n";
    EXPECT_GT(glyph_v, black_v_max + 60) << shape_name(shapes[i]);
    EXPECT_GT(glyph_v * 10, placard_v * 6) << shape_name(shapes[i]);
    EXPECT_LT(glyph_s, 100) << shape_name(shapes[i]);
  }
  for (std::size_t k = 0; k < out.count; ++k) {
    const msg::Detection& d = out.detections[k];
    const cv::Point c(static_cast<int>(d.center_x_px), static_cast<int>(d.center_y_px));
    const bool on_placard = std::any_of(placards.begin(), placards.end(),
                                        [&](const cv::Rect& p) { return p.contains(c); });
    if (on_placard) continue;
    std::cout << "[ photo ] reported off every placard: " << colour_name(d.colour) << "/"
              << shape_name(d.shape) << " at " << c.x << "," << c.y << "\n";
    // Beyond the last post (x about 510) and below the placards' tops: the grass bank.
    EXPECT_GT(c.x, 500) << colour_name(d.colour) << "/" << shape_name(d.shape);
  }
}

}  // namespace
}  // namespace coxswain::perception
