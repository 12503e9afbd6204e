// SPDX-License-Identifier: Apache-2.0
#include "sim/sensors/camera_sim.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "coxswain/core/angles.hpp"

namespace coxswain::sim::sensors {

namespace {
constexpr double kNearM = 0.05;  // near clipping plane
constexpr int kNoiseFrames = 4;  // pre-drawn noise frames, picked at random per frame
constexpr int kCircleVertices = 40;

const cv::Scalar kSkyTop{235, 205, 180};  // pale blue-grey: below every saturation floor
const cv::Scalar kSkyHorizon{240, 232, 222};
const cv::Scalar kWaterFar{128, 122, 104};  // grey-green, low saturation
const cv::Scalar kWaterNear{100, 100, 80};
const cv::Scalar kWall{165, 170, 172};
const cv::Scalar kPlacardFront{245, 245, 245};
const cv::Scalar kPlacardBack{150, 150, 150};
constexpr int kWaveFrames = 4;  // venue backgrounds with different wave phases

/// Sky and water of a venue (before its light is applied) and how rough and glinting the sea is.
struct VenueLook {
  cv::Scalar sky_top;
  cv::Scalar sky_horizon;
  cv::Scalar water_far;
  cv::Scalar water_near;
  double wave_amplitude = 0.0;           // brightness modulation of the crests, fraction
  int glints = 0;                        // bright specks on the water per frame
  cv::Scalar light_gain{1.0, 1.0, 1.0};  // per channel (B, G, R), applied to everything
  double desaturation = 0.0;             // 0 = none, 1 = grey
};

VenueLook venue_look(Venue v) {
  switch (v) {
    case Venue::kHarbour:  // blue sky and blue-green sea, hue about 100, saturation 130-150
      return {{200, 150, 95},
              {225, 205, 180},
              {150, 132, 72},
              {120, 100, 50},
              0.12,
              160,
              {1.0, 1.0, 1.0},
              0.0};
    case Venue::kOvercast:  // grey sky, dull green-grey sea, everything in shade
      return {{205, 205, 200},
              {215, 215, 212},
              {105, 118, 92},
              {82, 96, 70},
              0.08,
              0,
              {0.72, 0.72, 0.72},
              0.3};
    case Venue::kLowSun:  // warm light, orange sky at the horizon, dark sea with a glint path
      return {{190, 150, 130},
              {110, 165, 215},
              {120, 95, 45},
              {95, 75, 35},
              0.10,
              260,
              {0.8, 0.92, 1.1},
              0.0};
    case Venue::kPool:
      break;
  }
  return {kSkyTop, kSkyHorizon, kWaterFar, kWaterNear, 0.0, 0, {1.0, 1.0, 1.0}, 0.0};
}

/// A marker glyph in the placard plane, (right, up) metres from its centre, width `s`.
void glyph(msg::Shape shape, double s, std::vector<cv::Point2d>& out) {
  out.clear();
  const double h = 0.5 * s;
  switch (shape) {
    case msg::Shape::kTriangle: {
      const double half_height = s * std::sqrt(3.0) / 4.0;
      out = {{-h, -half_height}, {h, -half_height}, {0.0, half_height}};
      break;
    }
    case msg::Shape::kRectangle:
      out = {{-h, -h}, {h, -h}, {h, h}, {-h, h}};
      break;
    case msg::Shape::kCross: {
      const double a = s / 6.0;  // arms a third of the width
      out = {{-a, h}, {a, h},   {a, a},   {h, a},   {h, -a}, {a, -a},
             {a, -h}, {-a, -h}, {-a, -a}, {-h, -a}, {-h, a}, {-a, a}};
      break;
    }
    case msg::Shape::kCircle:
    case msg::Shape::kBuoy:
    case msg::Shape::kUnknown:
      for (int i = 0; i < kCircleVertices; ++i) {
        const double a = 2.0 * core::kPi * i / kCircleVertices;
        out.emplace_back(h * std::cos(a), h * std::sin(a));
      }
      break;
  }
}
}  // namespace

std::string_view venue_name(Venue v) {
  switch (v) {
    case Venue::kPool:
      return "pool";
    case Venue::kHarbour:
      return "harbour";
    case Venue::kOvercast:
      return "overcast";
    case Venue::kLowSun:
      return "low_sun";
  }
  return "pool";
}

std::optional<Venue> parse_venue(std::string_view name) {
  for (const Venue v : {Venue::kPool, Venue::kHarbour, Venue::kOvercast, Venue::kLowSun}) {
    if (name == venue_name(v)) return v;
  }
  return std::nullopt;
}

cv::Scalar paint_bgr(msg::Colour colour) {
  switch (colour) {
    case msg::Colour::kRed:
      return {36, 28, 237};
    case msg::Colour::kGreen:
      return {76, 177, 34};
    case msg::Colour::kBlue:
      return {204, 72, 63};
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

std::optional<std::string> CameraSimConfig::validate() const {
  if (width_px < 16 || width_px > 4096 || height_px < 16 || height_px > 4096) {
    return "camera width_px/height_px in [16, 4096]";
  }
  if (!(hfov_deg > 10.0 && hfov_deg < 170.0)) return "camera hfov_deg in (10, 170)";
  if (!(rate_hz > 0.0 && rate_hz <= 120.0)) return "camera rate_hz in (0, 120]";
  if (!std::isfinite(mount.yaw_deg) || !std::isfinite(mount.x_m) || !std::isfinite(mount.y_m)) {
    return "camera mount must be finite";
  }
  if (!(height_m > 0.0 && height_m <= 10.0)) return "camera height_m in (0, 10]";
  if (!(tilt_down_deg >= -30.0 && tilt_down_deg <= 60.0))
    return "camera tilt_down_deg in [-30, 60]";
  if (!(wall_piece_m >= 0.1 && wall_piece_m <= 20.0)) return "camera wall_piece_m in [0.1, 20]";
  if (!(glare_gain >= 0.1 && glare_gain <= 10.0)) return "camera glare_gain in [0.1, 10]";
  if (!(glare_saturation_loss >= 0.0 && glare_saturation_loss <= 1.0)) {
    return "camera glare_saturation_loss in [0, 1]";
  }
  if (!std::isfinite(sun_bearing_deg) ||
      !(sun_elevation_deg >= -10.0 && sun_elevation_deg <= 90.0)) {
    return "camera sun_bearing_deg finite, sun_elevation_deg in [-10, 90]";
  }
  if (!(sun_blob_radius_px >= 0.0 && sun_blob_radius_px <= 1000.0)) {
    return "camera sun_blob_radius_px in [0, 1000]";
  }
  if (blur_kernel_px != 0 &&
      (blur_kernel_px < 3 || blur_kernel_px % 2 == 0 || blur_kernel_px > 31)) {
    return "camera blur_kernel_px must be 0 (off) or odd 3..31";
  }
  if (!(noise_sigma >= 0.0 && noise_sigma <= 100.0)) return "camera noise_sigma in [0, 100]";
  return {};
}

CameraSim::CameraSim(const CameraSimConfig& config, const world::World& world)
    : config_(config), rng_(config.seed) {
  focal_px_ = 0.5 * config_.width_px / std::tan(core::deg_to_rad(0.5 * config_.hfov_deg));
  cos_tilt_ = std::cos(core::deg_to_rad(config_.tilt_down_deg));
  sin_tilt_ = std::sin(core::deg_to_rad(config_.tilt_down_deg));
  period_ns_ = static_cast<core::TimeNs>(std::llround(1e9 / config_.rate_hz));
  // Walls in short pieces so that sorting pieces by distance paints them in a sound order.
  const auto add_wall = [this](const world::Wall& w) {
    for (std::size_t i = 1; i < w.points.size(); ++i) {
      const core::NavPoint a = w.points[i - 1];
      const core::NavPoint b = w.points[i];
      const double len = core::distance_m(a, b);
      const int n = std::max(1, static_cast<int>(std::ceil(len / config_.wall_piece_m)));
      for (int k = 0; k < n; ++k) {
        const double f0 = static_cast<double>(k) / n;
        const double f1 = static_cast<double>(k + 1) / n;
        walls_.push_back(
            {{a.north_m + f0 * (b.north_m - a.north_m), a.east_m + f0 * (b.east_m - a.east_m)},
             {a.north_m + f1 * (b.north_m - a.north_m), a.east_m + f1 * (b.east_m - a.east_m)},
             w.height_m});
      }
    }
  };
  for (const world::Wall& w : world.walls) add_wall(w);
  for (const world::Dock& d : world.docks) {
    for (const world::Wall& w : d.walls) add_wall(w);
    markers_.push_back(d.marker);
  }
  buoys_ = world.buoys;
  items_.reserve(walls_.size() + buoys_.size() + markers_.size());
  build_background();
  if (config_.venue != Venue::kPool) build_venue_backgrounds();

  if (config_.noise_sigma > 0.0) {
    // Signed noise kept as its positive and negative parts (8-bit each), so applying it is two
    // saturating 8-bit operations instead of a mixed-type add.
    cv::RNG cv_rng(rng_.next_u64());
    cv::Mat n(config_.height_px, config_.width_px, CV_16SC3);
    for (int i = 0; i < kNoiseFrames; ++i) {
      cv_rng.fill(n, cv::RNG::NORMAL, cv::Scalar::all(0), cv::Scalar::all(config_.noise_sigma));
      cv::Mat pos;
      cv::Mat neg;
      n.convertTo(pos, CV_8U);        // saturates negatives to 0
      n.convertTo(neg, CV_8U, -1.0);  // the negative part, as a positive amount
      noise_frames_.push_back(pos);
      noise_frames_.push_back(neg);
    }
  }
  if (config_.glare && config_.sun_blob_radius_px > 0.0) {
    const int r = static_cast<int>(std::ceil(3.0 * config_.sun_blob_radius_px));
    blob_.create(2 * r + 1, 2 * r + 1, CV_8UC3);
    const double s2 = 2.0 * config_.sun_blob_radius_px * config_.sun_blob_radius_px;
    for (int y = -r; y <= r; ++y) {
      for (int x = -r; x <= r; ++x) {
        const auto v = static_cast<unsigned char>(
            std::lround(255.0 * std::exp(-static_cast<double>(x * x + y * y) / s2)));
        blob_.at<cv::Vec3b>(y + r, x + r) = {v, v, v};
      }
    }
  }
}

void CameraSim::build_background() {
  background_.create(config_.height_px, config_.width_px, CV_8UC3);
  const double cy = 0.5 * config_.height_px;
  // Horizon: the image row of points at infinity on the water.
  const double horizon = cy - focal_px_ * sin_tilt_ / cos_tilt_;
  for (int y = 0; y < config_.height_px; ++y) {
    const double row = static_cast<double>(y) + 0.5;
    cv::Scalar c;
    if (row < horizon) {
      const double t = std::clamp(row / std::max(1.0, horizon), 0.0, 1.0);
      c = kSkyTop * (1.0 - t) + kSkyHorizon * t;
    } else {
      const double t =
          std::clamp((row - horizon) / std::max(1.0, config_.height_px - horizon), 0.0, 1.0);
      c = kWaterFar * (1.0 - t) + kWaterNear * t;
    }
    background_.row(y).setTo(c);
  }
}

void CameraSim::build_venue_backgrounds() {
  const VenueLook look = venue_look(config_.venue);
  const int w = config_.width_px;
  const int h = config_.height_px;
  const double cy = 0.5 * h;
  const double horizon = cy - focal_px_ * sin_tilt_ / cos_tilt_;
  for (int f = 0; f < kWaveFrames; ++f) {
    cv::Mat img(h, w, CV_8UC3);
    const double phase = 2.0 * core::kPi * rng_.uniform(0.0, 1.0);
    const double cross_phase = 2.0 * core::kPi * rng_.uniform(0.0, 1.0);
    for (int y = 0; y < h; ++y) {
      const double row = static_cast<double>(y) + 0.5;
      auto* px = img.ptr<cv::Vec3b>(y);
      if (row < horizon) {
        const double t = std::clamp(row / std::max(1.0, horizon), 0.0, 1.0);
        const cv::Scalar c = look.sky_top * (1.0 - t) + look.sky_horizon * t;
        for (int x = 0; x < w; ++x) {
          px[x] = cv::Vec3b(cv::saturate_cast<uchar>(c[0]), cv::saturate_cast<uchar>(c[1]),
                            cv::saturate_cast<uchar>(c[2]));
        }
        continue;
      }
      const double t = std::clamp((row - horizon) / std::max(1.0, h - horizon), 0.0, 1.0);
      const cv::Scalar base = look.water_far * (1.0 - t) + look.water_near * t;
      // Crest lines run parallel to the horizon, 2 m apart on the water: the row's distance
      // (camera height * focal / rows below the horizon) sets their phase; a slower ripple
      // across the row breaks them up.
      const double depth_m = config_.height_m * focal_px_ / std::max(0.5, row - horizon);
      const double ripple_px = 8.0 + 80.0 * t;
      for (int x = 0; x < w; ++x) {
        const double s = std::sin(2.0 * core::kPi * depth_m / 2.0 + phase +
                                  0.8 * std::sin(2.0 * core::kPi * x / ripple_px + cross_phase));
        const double k = 1.0 + look.wave_amplitude * s;
        px[x] = cv::Vec3b(cv::saturate_cast<uchar>(base[0] * k + 6.0 * s),
                          cv::saturate_cast<uchar>(base[1] * k + 8.0 * s),
                          cv::saturate_cast<uchar>(base[2] * k + 3.0 * s));
      }
    }
    // Sun glint: small white specks, denser towards the horizon.
    for (int i = 0; i < look.glints; ++i) {
      const double u = rng_.uniform(0.0, 1.0);
      const double y = horizon + (h - horizon) * u * u;
      const double x = rng_.uniform(0.0, static_cast<double>(w));
      const int r = 1 + static_cast<int>(rng_.uniform(0.0, 2.0 + 3.0 * u));
      if (y < 0.0 || y >= h) continue;
      cv::ellipse(img, cv::Point(static_cast<int>(x), static_cast<int>(y)), cv::Size(r + 1, r), 0.0,
                  0.0, 360.0, cv::Scalar(250, 250, 248), cv::FILLED, cv::LINE_8);
    }
    venue_backgrounds_.push_back(img);
  }
}

void CameraSim::apply_light(cv::Mat& img) {
  const VenueLook look = venue_look(config_.venue);
  if (look.desaturation > 0.0) {
    cv::cvtColor(img, grey_, cv::COLOR_BGR2GRAY);
    cv::cvtColor(grey_, grey3_, cv::COLOR_GRAY2BGR);
    cv::addWeighted(img, 1.0 - look.desaturation, grey3_, look.desaturation, 0.0, img);
  }
  if (look.light_gain != cv::Scalar(1.0, 1.0, 1.0)) cv::multiply(img, look.light_gain, img);
}

std::optional<cv::Rect2d> CameraSim::marker_box(const core::NavPose& pose,
                                                const world::Marker& m) const {
  const View v = view_of(pose);
  const double face = core::deg_to_rad(m.facing_deg);
  const double fn = std::cos(face);
  const double fe = std::sin(face);
  if ((v.eye.north_m - m.center.north_m) * fn + (v.eye.east_m - m.center.east_m) * fe <= 0.0) {
    return std::nullopt;
  }
  std::vector<cv::Point2d> g;
  glyph(m.shape, m.size_m, g);
  double x0 = 1e18;
  double y0 = 1e18;
  double x1 = -1e18;
  double y1 = -1e18;
  for (const cv::Point2d& p : g) {
    const Vec3 c =
        to_camera(v, {m.center.north_m + p.x * fe, m.center.east_m - p.x * fn}, m.height_m + p.y);
    if (c.fwd < kNearM) return std::nullopt;
    const double x = 0.5 * config_.width_px + focal_px_ * c.right / c.fwd;
    const double y = 0.5 * config_.height_px - focal_px_ * c.up / c.fwd;
    x0 = std::min(x0, x);
    x1 = std::max(x1, x);
    y0 = std::min(y0, y);
    y1 = std::max(y1, y);
  }
  return cv::Rect2d(x0, y0, x1 - x0, y1 - y0);
}

std::optional<cv::Rect2d> CameraSim::buoy_box(const core::NavPose& pose,
                                              const world::Buoy& b) const {
  const Vec3 c = to_camera(view_of(pose), b.center, 0.5 * b.height_m);
  if (c.fwd < kNearM + b.radius_m) return std::nullopt;
  const double x = 0.5 * config_.width_px + focal_px_ * c.right / c.fwd;
  const double y = 0.5 * config_.height_px - focal_px_ * c.up / c.fwd;
  const double ax = focal_px_ * b.radius_m / c.fwd;
  const double ay = focal_px_ * 0.5 * b.height_m / c.fwd;
  return cv::Rect2d(x - ax, y - ay, 2.0 * ax, 2.0 * ay);
}

CameraSim::View CameraSim::view_of(const core::NavPose& pose) const {
  View v;
  v.eye = core::body_to_nav(pose, {config_.mount.x_m, config_.mount.y_m});
  const double yaw = core::deg_to_rad(pose.heading_deg + config_.mount.yaw_deg);
  v.cos_yaw = std::cos(yaw);
  v.sin_yaw = std::sin(yaw);
  return v;
}

CameraSim::Vec3 CameraSim::to_camera(const View& v, core::NavPoint p, double up_m) const {
  const double dn = p.north_m - v.eye.north_m;
  const double de = p.east_m - v.eye.east_m;
  const double fwd = dn * v.cos_yaw + de * v.sin_yaw;
  const double right = -dn * v.sin_yaw + de * v.cos_yaw;
  const double up = up_m - config_.height_m;
  return {fwd * cos_tilt_ - up * sin_tilt_, right, fwd * sin_tilt_ + up * cos_tilt_};
}

bool CameraSim::project(const core::NavPose& pose, core::NavPoint p, double up_m,
                        cv::Point2d& px) const {
  const Vec3 c = to_camera(view_of(pose), p, up_m);
  if (c.fwd < kNearM) return false;
  px.x = 0.5 * config_.width_px + focal_px_ * c.right / c.fwd;
  px.y = 0.5 * config_.height_px - focal_px_ * c.up / c.fwd;
  return true;
}

double CameraSim::bearing_in_image_deg(const core::NavPose& pose, core::NavPoint p) const {
  const Vec3 c = to_camera(view_of(pose), p, config_.height_m);
  return core::rad_to_deg(std::atan2(c.right, c.fwd));
}

bool CameraSim::project_polygon(const std::vector<Vec3>& poly, std::vector<cv::Point>& out) {
  // Sutherland-Hodgman against the near plane fwd >= kNearM.
  clipped_.clear();
  const std::size_t n = poly.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3& a = poly[i];
    const Vec3& b = poly[(i + 1) % n];
    const bool a_in = a.fwd >= kNearM;
    const bool b_in = b.fwd >= kNearM;
    if (a_in) clipped_.push_back(a);
    if (a_in != b_in) {
      const double t = (kNearM - a.fwd) / (b.fwd - a.fwd);
      clipped_.push_back({kNearM, a.right + t * (b.right - a.right), a.up + t * (b.up - a.up)});
    }
  }
  if (clipped_.size() < 3) return false;
  out.clear();
  const double cx = 0.5 * config_.width_px;
  const double cy = 0.5 * config_.height_px;
  // Fixed point (shift 4) keeps sub-pixel vertex precision for fillPoly.
  constexpr double kScale = 16.0;
  bool any_left = false;
  bool any_right = false;
  for (const Vec3& c : clipped_) {
    const double x = cx + focal_px_ * c.right / c.fwd;
    const double y = cy - focal_px_ * c.up / c.fwd;
    any_left = any_left || x >= 0.0;
    any_right = any_right || x <= config_.width_px;
    const double lim = 1e5;  // keep far-off vertices of near clipped polygons in int range
    out.emplace_back(static_cast<int>(std::lround(std::clamp(x, -lim, lim) * kScale)),
                     static_cast<int>(std::lround(std::clamp(y, -lim, lim) * kScale)));
  }
  return any_left && any_right;
}

void CameraSim::draw_wall(const View& v, const WallPiece& w, cv::Mat& img) {
  poly3_ = {to_camera(v, w.a, 0.0), to_camera(v, w.b, 0.0), to_camera(v, w.b, w.height_m),
            to_camera(v, w.a, w.height_m)};
  if (!project_polygon(poly3_, poly2_)) return;
  cv::fillConvexPoly(img, poly2_, kWall, cv::LINE_8, 4);
}

void CameraSim::draw_buoy(const View& v, const world::Buoy& b, cv::Mat& img) {
  const Vec3 c = to_camera(v, b.center, 0.5 * b.height_m);
  if (c.fwd < kNearM + b.radius_m) return;
  const double x = 0.5 * config_.width_px + focal_px_ * c.right / c.fwd;
  const double y = 0.5 * config_.height_px - focal_px_ * c.up / c.fwd;
  const double ax = focal_px_ * b.radius_m / c.fwd;
  const double ay = focal_px_ * 0.5 * b.height_m / c.fwd;
  if (x + ax < 0.0 || x - ax > config_.width_px || ax > 4.0 * config_.width_px) return;
  constexpr double kScale = 16.0;
  cv::ellipse(img,
              cv::Point(static_cast<int>(std::lround(x * kScale)),
                        static_cast<int>(std::lround(y * kScale))),
              cv::Size(static_cast<int>(std::lround(ax * kScale)),
                       static_cast<int>(std::lround(ay * kScale))),
              0.0, 0.0, 360.0, paint_bgr(b.colour), cv::FILLED, cv::LINE_8, 4);
}

void CameraSim::draw_marker(const View& v, const world::Marker& m, cv::Mat& img) {
  const double face = core::deg_to_rad(m.facing_deg);
  const double fn = std::cos(face);
  const double fe = std::sin(face);
  // Seen from the front the placard's right is the facing direction turned 90 deg to port.
  const double rn = fe;
  const double re = -fn;
  const bool front =
      (v.eye.north_m - m.center.north_m) * fn + (v.eye.east_m - m.center.east_m) * fe > 0.0;
  const auto corner = [&](double right_m, double up_m) {
    return to_camera(v, {m.center.north_m + right_m * rn, m.center.east_m + right_m * re},
                     m.height_m + up_m);
  };
  const double b = 0.7 * m.size_m;  // placard half-width: a white margin around the glyph
  poly3_ = {corner(-b, -b), corner(b, -b), corner(b, b), corner(-b, b)};
  if (!project_polygon(poly3_, poly2_)) return;
  cv::fillConvexPoly(img, poly2_, front ? kPlacardFront : kPlacardBack, cv::LINE_8, 4);
  if (!front) return;
  glyph(m.shape, m.size_m, glyph_);
  poly3_.clear();
  for (const cv::Point2d& p : glyph_) poly3_.push_back(corner(p.x, p.y));
  if (!project_polygon(poly3_, poly2_)) return;
  const cv::Point* pts = poly2_.data();
  const int count = static_cast<int>(poly2_.size());
  cv::fillPoly(img, &pts, &count, 1, paint_bgr(m.colour), cv::LINE_8, 4);
}

void CameraSim::apply_effects(const core::NavPose& pose, cv::Mat& img) {
  if (config_.glare) {
    if (config_.glare_saturation_loss > 0.0) {
      cv::cvtColor(img, grey_, cv::COLOR_BGR2GRAY);
      cv::cvtColor(grey_, grey3_, cv::COLOR_GRAY2BGR);
      cv::addWeighted(img, 1.0 - config_.glare_saturation_loss, grey3_,
                      config_.glare_saturation_loss, 0.0, img);
    }
    if (config_.glare_gain != 1.0) img.convertTo(img, -1, config_.glare_gain, 0.0);
    if (!blob_.empty()) {
      // The sun's image point (at infinity): direction in camera axes.
      const View v = view_of(pose);
      const double el = core::deg_to_rad(config_.sun_elevation_deg);
      const double az = core::deg_to_rad(config_.sun_bearing_deg);
      const double dn = std::cos(el) * std::cos(az);
      const double de = std::cos(el) * std::sin(az);
      const double fwd = dn * v.cos_yaw + de * v.sin_yaw;
      const double right = -dn * v.sin_yaw + de * v.cos_yaw;
      const double up = std::sin(el);
      const double depth = fwd * cos_tilt_ - up * sin_tilt_;
      if (depth > 1e-3) {
        const double cam_up = fwd * sin_tilt_ + up * cos_tilt_;
        const int x =
            static_cast<int>(std::lround(0.5 * config_.width_px + focal_px_ * right / depth));
        const int y =
            static_cast<int>(std::lround(0.5 * config_.height_px - focal_px_ * cam_up / depth));
        const int r = blob_.cols / 2;
        const cv::Rect dst =
            cv::Rect(x - r, y - r, blob_.cols, blob_.rows) & cv::Rect(0, 0, img.cols, img.rows);
        if (dst.area() > 0) {
          const cv::Rect src(dst.x - (x - r), dst.y - (y - r), dst.width, dst.height);
          cv::Mat roi = img(dst);
          cv::add(roi, blob_(src), roi);
        }
      }
    }
  }
  if (config_.blur_kernel_px >= 3) {
    cv::GaussianBlur(img, img, cv::Size(config_.blur_kernel_px, config_.blur_kernel_px), 0.0);
  }
  if (!noise_frames_.empty()) {
    const auto k = 2 * static_cast<std::size_t>(rng_.next_u64() % (noise_frames_.size() / 2));
    cv::add(img, noise_frames_[k], img);
    cv::subtract(img, noise_frames_[k + 1], img);
  }
}

void CameraSim::render(const core::NavPose& pose, cv::Mat& out) {
  if (venue_backgrounds_.empty()) {
    background_.copyTo(out);
  } else {
    venue_backgrounds_[static_cast<std::size_t>(rng_.next_u64() % venue_backgrounds_.size())]
        .copyTo(out);
  }
  const View v = view_of(pose);
  items_.clear();
  for (std::size_t i = 0; i < walls_.size(); ++i) {
    const core::NavPoint mid{0.5 * (walls_[i].a.north_m + walls_[i].b.north_m),
                             0.5 * (walls_[i].a.east_m + walls_[i].b.east_m)};
    items_.push_back({core::distance_m(v.eye, mid), 0, i});
  }
  for (std::size_t i = 0; i < buoys_.size(); ++i) {
    items_.push_back({core::distance_m(v.eye, buoys_[i].center) - buoys_[i].radius_m, 1, i});
  }
  for (std::size_t i = 0; i < markers_.size(); ++i) {
    // Slightly nearer than its own wall so the placard is painted over the wall behind it.
    items_.push_back({core::distance_m(v.eye, markers_[i].center) - 0.15, 2, i});
  }
  std::sort(items_.begin(), items_.end(),
            [](const Item& a, const Item& b) { return a.distance_m > b.distance_m; });
  for (const Item& it : items_) {
    switch (it.kind) {
      case 0:
        draw_wall(v, walls_[it.index], out);
        break;
      case 1:
        draw_buoy(v, buoys_[it.index], out);
        break;
      default:
        draw_marker(v, markers_[it.index], out);
        break;
    }
  }
  if (config_.venue != Venue::kPool) apply_light(out);
  apply_effects(pose, out);
}

bool CameraSim::update(core::TimeNs now_ns, const core::NavPose& pose, cv::Mat& out) {
  const core::TimeNs t_ns = now_ns >= 0 ? (now_ns / period_ns_) * period_ns_
                                        : -((-now_ns + period_ns_ - 1) / period_ns_) * period_ns_;
  if (last_frame_ns_ != core::kNeverNs && t_ns <= last_frame_ns_) return false;
  last_frame_ns_ = t_ns;
  render(pose, out);
  return true;
}

}  // namespace coxswain::sim::sensors
