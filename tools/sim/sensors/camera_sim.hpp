// SPDX-License-Identifier: Apache-2.0
#pragma once
// Simulated camera: a pinhole at the configured field of view, resolution, mount and height above
// the water, rendering (OpenCV core/imgproc only) sky, horizon, water, buoys, walls and the dock
// placards with their marker shapes projected in perspective onto the placard's plane, painted far
// to near so nearer objects hide farther ones. Options: sun glare / over-exposure (gain,
// saturation loss, a bright blob where the sun is), Gaussian blur and pixel noise, all seeded.
// Frames are BGR (CV_8UC3) as the camera driver delivers them. Not thread-safe; no allocation per
// frame once the first frame of a size is rendered.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <opencv2/core.hpp>

#include "coxswain/core/frames.hpp"
#include "coxswain/core/time.hpp"
#include "coxswain/msg/camera_detections.hpp"
#include "sim/rng/rng.hpp"
#include "sim/world/world.hpp"

namespace coxswain::sim::sensors {

/// Where the boat sails, for the renderer's sky, water and light. kPool: grey-green calm water,
/// pale sky (the detectors' original test scene). kHarbour: blue-green sea (hue about 100,
/// saturation 120-160) with waves and sun glint under a blue sky. kOvercast: grey sky, dull
/// green-grey sea, everything in shade (darker, less saturated). kLowSun: warm light from low in
/// the sky, an orange sky near the horizon, a dark sea with a glint path.
enum class Venue : std::uint8_t { kPool, kHarbour, kOvercast, kLowSun };
[[nodiscard]] std::string_view venue_name(Venue v);
[[nodiscard]] std::optional<Venue> parse_venue(std::string_view name);

struct CameraSimConfig {
  int width_px = 640;  // devices.yaml camera
  int height_px = 480;
  double hfov_deg = 80.0;
  double rate_hz = 10.0;                       // frames rendered per second of simulation
  core::MountTransform mount{0.0, 0.05, 0.0};  // boat.yaml mounts.camera
  double height_m = 0.6;                       // optical centre above the water
  double tilt_down_deg = 0.0;                  // optical axis below the horizon
  double wall_piece_m = 1.0;  // walls are painted in pieces this long (painter's order)
  // Sun glare / over-exposure.
  bool glare = false;
  double glare_gain = 1.5;             // brightness multiplier (saturates at 255)
  double glare_saturation_loss = 0.4;  // 0 = none, 1 = grey
  double sun_bearing_deg = 0.0;        // navigation bearing of the sun
  double sun_elevation_deg = 25.0;
  double sun_blob_radius_px = 60.0;  // 1-sigma of the bright blob; 0 = no blob
  int blur_kernel_px = 0;            // Gaussian blur, odd; 0 = off
  double noise_sigma = 0.0;          // pixel noise, grey levels; 0 = off
  Venue venue = Venue::kPool;
  std::uint64_t seed = 4;

  [[nodiscard]] std::optional<std::string> validate() const;
};

/// BGR paint of each colour (saturated placard paints the default HSV ranges accept).
[[nodiscard]] cv::Scalar paint_bgr(msg::Colour colour);

class CameraSim {
 public:
  CameraSim(const CameraSimConfig& config, const world::World& world);

  /// Renders the view from the boat at `pose` into `out` (re-allocated only when its size or type
  /// differs).
  void render(const core::NavPose& pose, cv::Mat& out);
  /// Renders a frame when one is due at `now_ns` (multiples of 1/rate_hz); true when rendered.
  bool update(core::TimeNs now_ns, const core::NavPose& pose, cv::Mat& out);

  /// Image point of a navigation-frame point at `up_m` above the water seen from `pose`;
  /// false when behind the camera. Pixel coordinates, x right, y down.
  [[nodiscard]] bool project(const core::NavPose& pose, core::NavPoint p, double up_m,
                             cv::Point2d& px) const;
  /// Camera-frame bearing (+ right) of a point seen from `pose`, degrees.
  [[nodiscard]] double bearing_in_image_deg(const core::NavPose& pose, core::NavPoint p) const;
  /// Image bounding box (x right, y down, pixels) of a marker's glyph or a buoy seen from `pose`;
  /// nullopt when behind the camera or (marker) seen from the back.
  [[nodiscard]] std::optional<cv::Rect2d> marker_box(const core::NavPose& pose,
                                                     const world::Marker& m) const;
  [[nodiscard]] std::optional<cv::Rect2d> buoy_box(const core::NavPose& pose,
                                                   const world::Buoy& b) const;
  [[nodiscard]] double focal_px() const { return focal_px_; }
  [[nodiscard]] const CameraSimConfig& config() const { return config_; }

 private:
  struct Vec3 {
    double fwd = 0.0;  // along the optical axis (depth)
    double right = 0.0;
    double up = 0.0;
  };
  struct WallPiece {
    core::NavPoint a;
    core::NavPoint b;
    double height_m = 0.5;
  };
  struct Item {
    double distance_m = 0.0;
    int kind = 0;  // 0 wall piece, 1 buoy, 2 marker
    std::size_t index = 0;
  };
  struct View {
    core::NavPoint eye;
    double cos_yaw = 1.0;
    double sin_yaw = 0.0;
  };

  [[nodiscard]] View view_of(const core::NavPose& pose) const;
  [[nodiscard]] Vec3 to_camera(const View& v, core::NavPoint p, double up_m) const;
  /// Clips a camera-frame polygon at the near plane and projects it; false when nothing is left.
  bool project_polygon(const std::vector<Vec3>& poly, std::vector<cv::Point>& out);
  void build_background();
  void build_venue_backgrounds();
  void apply_light(cv::Mat& img);
  void draw_wall(const View& v, const WallPiece& w, cv::Mat& img);
  void draw_buoy(const View& v, const world::Buoy& b, cv::Mat& img);
  void draw_marker(const View& v, const world::Marker& m, cv::Mat& img);
  void apply_effects(const core::NavPose& pose, cv::Mat& img);

  CameraSimConfig config_;
  std::vector<WallPiece> walls_;
  std::vector<world::Buoy> buoys_;
  std::vector<world::Marker> markers_;
  Rng rng_;
  double focal_px_ = 1.0;
  double cos_tilt_ = 1.0;
  double sin_tilt_ = 0.0;
  cv::Mat background_;
  std::vector<cv::Mat> venue_backgrounds_;  // wave phases; one picked at random per frame
  std::vector<cv::Mat> noise_frames_;
  cv::Mat blob_;
  cv::Mat grey_;
  cv::Mat grey3_;
  std::vector<Item> items_;
  std::vector<Vec3> poly3_;
  std::vector<Vec3> clipped_;
  std::vector<cv::Point> poly2_;
  std::vector<cv::Point2d> glyph_;
  core::TimeNs last_frame_ns_ = core::kNeverNs;
  core::TimeNs period_ns_ = 0;
};

}  // namespace coxswain::sim::sensors
