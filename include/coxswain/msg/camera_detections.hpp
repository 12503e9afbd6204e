// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "coxswain/core/time.hpp"

namespace coxswain::msg {

enum class Colour : std::uint8_t {
  kUnknown = 0,
  kRed,
  kGreen,
  kBlue,
  kYellow,
  kOrange,
  kPurple,
  kBlack,
  kWhite
};
enum class Shape : std::uint8_t { kUnknown = 0, kTriangle, kRectangle, kCross, kCircle, kBuoy };

[[nodiscard]] constexpr std::string_view colour_name(Colour colour) {
  switch (colour) {
    case Colour::kUnknown:
      return "unknown";
    case Colour::kRed:
      return "red";
    case Colour::kGreen:
      return "green";
    case Colour::kBlue:
      return "blue";
    case Colour::kYellow:
      return "yellow";
    case Colour::kOrange:
      return "orange";
    case Colour::kPurple:
      return "purple";
    case Colour::kBlack:
      return "black";
    case Colour::kWhite:
      return "white";
  }
  return "unknown";
}

[[nodiscard]] constexpr std::string_view shape_name(Shape shape) {
  switch (shape) {
    case Shape::kUnknown:
      return "unknown";
    case Shape::kTriangle:
      return "triangle";
    case Shape::kRectangle:
      return "rectangle";
    case Shape::kCross:
      return "cross";
    case Shape::kCircle:
      return "circle";
    case Shape::kBuoy:
      return "buoy";
  }
  return "unknown";
}

/// One object seen in one frame. Bearing in the body frame (camera mount applied).
struct Detection {
  Colour colour = Colour::kUnknown;
  Shape shape = Shape::kUnknown;
  float bearing_deg = 0.0F;  // body frame, 0 = bow, + starboard
  float center_x_px = 0.0F;
  float center_y_px = 0.0F;
  float width_px = 0.0F;
  float height_px = 0.0F;
  float area_px = 0.0F;
  float score = 0.0F;  // 0..1, detector-specific confidence
};

/// Everything the camera thread found in one frame: small, so it travels through the store.
struct CameraDetections {
  static constexpr std::size_t kMaxDetections = 16;
  core::TimeNs stamp_ns = core::kNeverNs;  // frame capture time
  std::uint32_t frame_index = 0;
  std::uint16_t image_width_px = 0;
  std::uint16_t image_height_px = 0;
  std::uint32_t count = 0;
  std::array<Detection, kMaxDetections> detections{};

  [[nodiscard]] bool push(const Detection& d) {
    if (count >= kMaxDetections) return false;
    detections[count++] = d;
    return true;
  }
};

}  // namespace coxswain::msg
