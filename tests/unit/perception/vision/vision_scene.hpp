// SPDX-License-Identifier: Apache-2.0
#pragma once
// Synthetic camera frames for the vision tests and benchmark: filled shapes drawn with
// cv::fillPoly / cv::circle on a water-like background, plus the degradations a boat camera sees
// (rotation, perspective, blur, noise, over-exposure). Deterministic (seeded).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "coxswain/core/angles.hpp"
#include "coxswain/msg/camera_detections.hpp"

namespace coxswain::perception::testing {

/// Representative BGR paint for each colour (placard-like, saturated).
inline cv::Scalar paint_bgr(msg::Colour c) {
  switch (c) {
    case msg::Colour::kRed:
      return {36, 28, 237};  // #ED1C24
    case msg::Colour::kGreen:
      return {76, 177, 34};  // #22B14C
    case msg::Colour::kBlue:
      return {204, 72, 63};  // #3F48CC
    case msg::Colour::kYellow:
      return {0, 215, 240};
    case msg::Colour::kOrange:
      return {0, 130, 250};
    case msg::Colour::kPurple:
      return {160, 40, 130};
    case msg::Colour::kBlack:
      return {25, 25, 25};
    case msg::Colour::kWhite:
      return {245, 245, 245};
    case msg::Colour::kUnknown:
      break;
  }
  return {128, 128, 128};
}

/// BGR of an HSV triple in OpenCV 8-bit convention (hue 0..179).
inline cv::Scalar hsv_to_bgr(int h, int s, int v) {
  cv::Mat px(1, 1, CV_8UC3, cv::Scalar(h, s, v));
  cv::cvtColor(px, px, cv::COLOR_HSV2BGR);
  const cv::Vec3b b = px.at<cv::Vec3b>(0, 0);
  return {static_cast<double>(b[0]), static_cast<double>(b[1]), static_cast<double>(b[2])};
}

/// Grey-green water with a soft vertical gradient (low saturation: matches no colour range).
inline cv::Mat water_background(int width, int height) {
  cv::Mat img(height, width, CV_8UC3);
  for (int y = 0; y < height; ++y) {
    const double t = static_cast<double>(y) / std::max(1, height - 1);
    img.row(y).setTo(cv::Scalar(125.0 - 20.0 * t, 118.0 - 15.0 * t, 98.0 - 15.0 * t));
  }
  return img;
}

/// 640x480 open water: a sky gradient above the middle row, rippled water below (BGR), noise.
inline cv::Mat sea_background(cv::Scalar sky_top, cv::Scalar sky_horizon, cv::Scalar water_far,
                              cv::Scalar water_near, std::uint64_t seed, int width = 640,
                              int height = 480);

/// Harbour: blue sky, blue-green sea (hue about 97, saturation 130-150: inside the blue box).
inline cv::Mat harbour_scene(std::uint64_t seed, int width = 640, int height = 480) {
  return sea_background({200, 150, 95}, {225, 205, 180}, {150, 132, 72}, {120, 100, 50}, seed,
                        width, height);
}

/// Low sun: an orange sky near the horizon (hue about 13, saturation 160: inside the orange
/// box) over a dark sea.
inline cv::Mat low_sun_scene(std::uint64_t seed, int width = 640, int height = 480) {
  return sea_background({150, 140, 150}, {88, 152, 236}, {96, 87, 50}, {76, 69, 40}, seed, width,
                        height);
}

/// Outline of `shape` centred at `c`, fitting a `size_px` square, rotated by `rot_deg`.
/// Circles are returned as a 64-gon (only for perspective warps of the outline; drawing uses
/// cv::circle).
inline std::vector<cv::Point2f> shape_outline(msg::Shape shape, cv::Point2f c, float size_px,
                                              float rot_deg) {
  std::vector<cv::Point2f> pts;
  const float h = size_px / 2.0F;
  const double hd = static_cast<double>(h);
  switch (shape) {
    case msg::Shape::kTriangle:
      for (int k = 0; k < 3; ++k) {
        const double a = core::deg_to_rad(-90.0 + 120.0 * k);
        pts.emplace_back(static_cast<float>(hd * std::cos(a)),
                         static_cast<float>(hd * std::sin(a)));
      }
      break;
    case msg::Shape::kRectangle:
      pts = {{-h, -h}, {h, -h}, {h, h}, {-h, h}};
      break;
    case msg::Shape::kCross: {
      const float a = size_px / 6.0F;  // half arm width: arms 1/3 of the size wide
      pts = {{-a, -h}, {a, -h}, {a, -a}, {h, -a}, {h, a},   {a, a},
             {a, h},   {-a, h}, {-a, a}, {-h, a}, {-h, -a}, {-a, -a}};
      break;
    }
    default:
      for (int k = 0; k < 64; ++k) {
        const double a = 2.0 * core::kPi * k / 64.0;
        pts.emplace_back(static_cast<float>(hd * std::cos(a)),
                         static_cast<float>(hd * std::sin(a)));
      }
      break;
  }
  const double r = core::deg_to_rad(static_cast<double>(rot_deg));
  const auto cs = static_cast<float>(std::cos(r));
  const auto sn = static_cast<float>(std::sin(r));
  for (cv::Point2f& p : pts) p = {c.x + cs * p.x - sn * p.y, c.y + sn * p.x + cs * p.y};
  return pts;
}

/// Draws a filled shape (anti-aliased edges, as a real lens would blur them slightly).
inline void draw_shape(cv::Mat& img, msg::Shape shape, cv::Point2f c, float size_px, float rot_deg,
                       const cv::Scalar& bgr) {
  if (shape == msg::Shape::kCircle || shape == msg::Shape::kBuoy) {
    cv::circle(img,
               cv::Point(static_cast<int>(std::lround(c.x)), static_cast<int>(std::lround(c.y))),
               static_cast<int>(std::lround(size_px / 2.0F)), bgr, cv::FILLED, cv::LINE_AA);
    return;
  }
  const std::vector<cv::Point2f> outline = shape_outline(shape, c, size_px, rot_deg);
  std::vector<cv::Point> poly;
  for (const cv::Point2f& p : outline) {
    poly.emplace_back(static_cast<int>(std::lround(p.x)), static_cast<int>(std::lround(p.y)));
  }
  const std::vector<std::vector<cv::Point>> polys{poly};
  cv::fillPoly(img, polys, bgr, cv::LINE_AA);
}

/// A white placard (square, 1.6x the marker) with the marker on it.
inline void draw_marker(cv::Mat& img, msg::Shape shape, msg::Colour colour, cv::Point2f c,
                        float size_px, float rot_deg) {
  const float p = size_px * 0.8F;
  cv::rectangle(img, cv::Point2f(c.x - p, c.y - p), cv::Point2f(c.x + p, c.y + p),
                paint_bgr(msg::Colour::kWhite), cv::FILLED);
  draw_shape(img, shape, c, size_px, rot_deg, paint_bgr(colour));
}

/// Keystone: the top edge shrinks by `shrink` of the width on each side (camera looking up at a
/// placard from the water), the bottom edge is kept.
inline void perspective_warp(cv::Mat& img, float shrink) {
  const auto w = static_cast<float>(img.cols);
  const auto h = static_cast<float>(img.rows);
  const std::array<cv::Point2f, 4> src{{{0, 0}, {w, 0}, {w, h}, {0, h}}};
  const std::array<cv::Point2f, 4> dst{
      {{shrink * w, 0.05F * h}, {(1 - shrink) * w, 0.05F * h}, {w, h}, {0, h}}};
  const cv::Mat m = cv::getPerspectiveTransform(src.data(), dst.data());
  cv::Mat out;
  cv::warpPerspective(img, out, m, img.size(), cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  img = out;
}

/// Additive Gaussian noise of `sigma` grey levels, seeded.
inline void add_noise(cv::Mat& img, double sigma, std::uint64_t seed) {
  cv::Mat noise(img.size(), CV_16SC3);
  cv::RNG rng(seed);
  rng.fill(noise, cv::RNG::NORMAL, cv::Scalar::all(0), cv::Scalar::all(sigma));
  cv::Mat wide;
  img.convertTo(wide, CV_16SC3);
  wide += noise;
  wide.convertTo(img, CV_8UC3);  // saturates
}

/// Strong sun: saturation scaled by `s_scale`, value raised by `v_add` (clipped).
inline void over_expose(cv::Mat& img, double s_scale, int v_add) {
  cv::Mat hsv;
  cv::cvtColor(img, hsv, cv::COLOR_BGR2HSV);
  for (int y = 0; y < hsv.rows; ++y) {
    auto* row = hsv.ptr<cv::Vec3b>(y);
    for (int x = 0; x < hsv.cols; ++x) {
      row[x][1] = cv::saturate_cast<std::uint8_t>(row[x][1] * s_scale);
      row[x][2] = cv::saturate_cast<std::uint8_t>(row[x][2] + v_add);
    }
  }
  cv::cvtColor(hsv, img, cv::COLOR_HSV2BGR);
}

inline cv::Mat sea_background(cv::Scalar sky_top, cv::Scalar sky_horizon, cv::Scalar water_far,
                              cv::Scalar water_near, std::uint64_t seed, int width, int height) {
  cv::Mat img(height, width, CV_8UC3);
  for (int y = 0; y < height; ++y) {
    const bool sky = y < height / 2;
    const double t = sky ? y / (0.5 * height) : (y - 0.5 * height) / (0.5 * height);
    const cv::Scalar base =
        sky ? sky_top * (1.0 - t) + sky_horizon * t : water_far * (1.0 - t) + water_near * t;
    for (int x = 0; x < width; ++x) {
      const double s = sky ? 0.0 : std::sin(0.9 * y + 0.8 * std::sin(x / (8.0 + 60.0 * t)));
      const double k = 1.0 + 0.12 * s;
      img.at<cv::Vec3b>(y, x) = cv::Vec3b(cv::saturate_cast<uchar>(base[0] * k + 6 * s),
                                          cv::saturate_cast<uchar>(base[1] * k + 8 * s),
                                          cv::saturate_cast<uchar>(base[2] * k + 3 * s));
    }
  }
  add_noise(img, 3.0, seed);
  return img;
}

}  // namespace coxswain::perception::testing
