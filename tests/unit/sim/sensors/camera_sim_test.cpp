// SPDX-License-Identifier: Apache-2.0
#include "sim/sensors/camera_sim.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "coxswain/core/angles.hpp"
#include "coxswain/perception/buoy_detector.hpp"
#include "coxswain/perception/marker_detector.hpp"
#include "coxswain/perception/vision_params.hpp"

namespace coxswain::sim::sensors {
namespace {

/// One dock whose back wall lies `distance_m` ahead of the origin, `lateral_m` to starboard,
/// with its placard facing the boat (south).
world::World dock_world(double distance_m, double lateral_m, msg::Colour colour, msg::Shape shape) {
  world::World w;
  world::Dock d;
  d.marker.colour = colour;
  d.marker.shape = shape;
  d.marker.size_m = 0.6;
  d.marker.height_m = 1.0;
  d.marker.center = {distance_m, lateral_m};
  d.marker.facing_deg = 180.0;
  const double back = distance_m + 0.05;
  d.walls.push_back({{{back - 2.0, lateral_m - 0.8},
                      {back, lateral_m - 0.8},
                      {back, lateral_m + 0.8},
                      {back - 2.0, lateral_m + 0.8}},
                     0.5});
  w.docks.push_back(d);
  return w;
}

CameraSimConfig plain_config() {
  CameraSimConfig c;
  c.noise_sigma = 3.0;
  return c;
}

TEST(CameraSim, EveryMarkerColourAndShapeFoundAtItsBearing) {
  perception::MarkerDetector detector;
  const msg::Colour colours[] = {msg::Colour::kRed,    msg::Colour::kGreen,  msg::Colour::kBlue,
                                 msg::Colour::kYellow, msg::Colour::kOrange, msg::Colour::kPurple,
                                 msg::Colour::kBlack};
  const msg::Shape shapes[] = {msg::Shape::kTriangle, msg::Shape::kRectangle, msg::Shape::kCross,
                               msg::Shape::kCircle};
  const core::NavPose pose{{0.0, 0.0}, 0.0};
  int cases = 0;
  for (const msg::Colour colour : colours) {
    for (const msg::Shape shape : shapes) {
      for (const double dist : {2.0, 4.5, 8.0}) {
        const double lateral = dist * 0.35 * ((cases % 3) - 1);  // left, centre, right
        const world::World w = dock_world(dist, lateral, colour, shape);
        CameraSim cam(plain_config(), w);
        cv::Mat frame;
        cam.render(pose, frame);
        ASSERT_EQ(frame.type(), CV_8UC3);
        ASSERT_EQ(frame.cols, 640);
        ASSERT_EQ(frame.rows, 480);
        msg::CameraDetections out;
        ASSERT_TRUE(detector.detect(frame, 0, out));
        const auto found = perception::find_target(out, colour, shape);
        ASSERT_TRUE(found.has_value()) << msg::colour_name(colour) << " " << static_cast<int>(shape)
                                       << " at " << dist << " m, lateral " << lateral;
        const double expected = cam.bearing_in_image_deg(pose, {dist, lateral});
        EXPECT_NEAR(found->bearing_deg, expected, 2.0)
            << msg::colour_name(colour) << " " << static_cast<int>(shape) << " at " << dist;
        ++cases;
      }
    }
  }
  EXPECT_EQ(cases, 7 * 4 * 3);
}

TEST(CameraSim, PlacardSeenFromBehindShowsNoMarker) {
  const world::World w = dock_world(4.0, 0.0, msg::Colour::kRed, msg::Shape::kTriangle);
  CameraSim cam(plain_config(), w);
  cv::Mat frame;
  cam.render({{8.0, 0.0}, 180.0}, frame);  // behind the dock, looking back at it
  perception::MarkerDetector detector;
  msg::CameraDetections out;
  ASSERT_TRUE(detector.detect(frame, 0, out));
  EXPECT_FALSE(perception::find_target(out, msg::Colour::kRed, msg::Shape::kTriangle).has_value());
}

TEST(CameraSim, PurpleBuoyFoundAndNearerBuoyHidesFarther) {
  world::World w;
  w.buoys.push_back({{6.0, 1.5}, 0.25, 0.6, msg::Colour::kPurple});
  w.buoys.push_back({{12.0, -6.0}, 0.25, 0.6, msg::Colour::kOrange});
  // A green buoy exactly behind a nearer red one: must be hidden.
  w.buoys.push_back({{4.0, -1.0}, 0.3, 0.6, msg::Colour::kRed});
  w.buoys.push_back({{8.0, -2.0}, 0.25, 0.6, msg::Colour::kGreen});
  CameraSim cam(plain_config(), w);
  const core::NavPose pose{{0.0, 0.0}, 0.0};
  cv::Mat frame;
  cam.render(pose, frame);
  perception::BuoyDetector detector;
  msg::CameraDetections out;
  ASSERT_TRUE(detector.detect(frame, 0, out));
  const msg::Detection* purple = perception::BuoyDetector::largest(out, msg::Colour::kPurple);
  ASSERT_NE(purple, nullptr);
  EXPECT_NEAR(purple->bearing_deg, cam.bearing_in_image_deg(pose, {6.0, 1.5}), 2.0);
  const msg::Detection* orange = perception::BuoyDetector::largest(out, msg::Colour::kOrange);
  ASSERT_NE(orange, nullptr);
  EXPECT_NEAR(orange->bearing_deg, cam.bearing_in_image_deg(pose, {12.0, -6.0}), 2.0);
  EXPECT_NE(perception::BuoyDetector::largest(out, msg::Colour::kRed), nullptr);
  EXPECT_EQ(perception::BuoyDetector::largest(out, msg::Colour::kGreen), nullptr);
  // Turning the boat moves the buoy across the image the right way: heading 20 deg to starboard
  // puts the purple buoy (bearing ~14 deg) to port.
  cam.render({{0.0, 0.0}, 20.0}, frame);
  ASSERT_TRUE(detector.detect(frame, 0, out));
  purple = perception::BuoyDetector::largest(out, msg::Colour::kPurple);
  ASSERT_NE(purple, nullptr);
  EXPECT_LT(purple->bearing_deg, -4.0);
}

TEST(CameraSim, GlareWashesOutBlurAndNoiseAreSeeded) {
  const world::World w = dock_world(4.0, 0.0, msg::Colour::kBlue, msg::Shape::kCircle);
  CameraSimConfig c = plain_config();
  c.glare = true;
  c.glare_gain = 1.6;
  c.glare_saturation_loss = 0.5;
  c.sun_bearing_deg = 10.0;
  c.sun_elevation_deg = 15.0;
  c.blur_kernel_px = 3;
  CameraSim glare(c, w);
  CameraSim plain(plain_config(), w);
  const core::NavPose pose{{0.0, 0.0}, 0.0};
  cv::Mat a;
  cv::Mat b;
  glare.render(pose, a);
  plain.render(pose, b);
  cv::Mat hsv_a;
  cv::Mat hsv_b;
  cv::cvtColor(a, hsv_a, cv::COLOR_BGR2HSV);
  cv::cvtColor(b, hsv_b, cv::COLOR_BGR2HSV);
  EXPECT_LT(cv::mean(hsv_a)[1], cv::mean(hsv_b)[1]);  // less saturated
  EXPECT_GT(cv::mean(hsv_a)[2], cv::mean(hsv_b)[2]);  // brighter
  // The sun blob near its image point is blown out.
  cv::Point2d sun_px;
  ASSERT_TRUE(glare.project(
      pose, {1000.0 * std::cos(core::deg_to_rad(10.0)), 1000.0 * std::sin(core::deg_to_rad(10.0))},
      c.height_m + 1000.0 * std::tan(core::deg_to_rad(15.0)), sun_px));
  const cv::Vec3b at_sun = a.at<cv::Vec3b>(static_cast<int>(sun_px.y), static_cast<int>(sun_px.x));
  EXPECT_GE(at_sun[0], 250);
  EXPECT_GE(at_sun[1], 250);
  // Same seed, same frame; another seed, other noise.
  CameraSim again(c, w);
  cv::Mat a2;
  again.render(pose, a2);
  EXPECT_EQ(cv::norm(a, a2, cv::NORM_INF), 0.0);
  c.seed = 77;
  CameraSim other(c, w);
  other.render(pose, a2);
  EXPECT_GT(cv::norm(a, a2, cv::NORM_INF), 0.0);
}

TEST(CameraSim, ModerateGlareStillDetectedSevereGlareWashesColoursOut) {
  // docs/missions.md: strong sun washes colours out. The default HSV floors are set for
  // moderately washed-out colours; a near-grey image must lose them.
  const world::World w = dock_world(4.0, 0.5, msg::Colour::kRed, msg::Shape::kTriangle);
  const core::NavPose pose{{0.0, 0.0}, 0.0};
  perception::MarkerDetector detector;
  msg::CameraDetections out;
  cv::Mat frame;
  CameraSimConfig c = plain_config();
  c.glare = true;
  c.sun_bearing_deg = -25.0;
  c.glare_gain = 1.3;
  c.glare_saturation_loss = 0.3;
  CameraSim moderate(c, w);
  moderate.render(pose, frame);
  ASSERT_TRUE(detector.detect(frame, 0, out));
  EXPECT_TRUE(perception::find_target(out, msg::Colour::kRed, msg::Shape::kTriangle).has_value());
  c.glare_gain = 1.8;
  c.glare_saturation_loss = 0.85;
  CameraSim severe(c, w);
  severe.render(pose, frame);
  ASSERT_TRUE(detector.detect(frame, 0, out));
  EXPECT_FALSE(perception::find_target(out, msg::Colour::kRed, msg::Shape::kTriangle).has_value());
}

TEST(CameraSim, PinholeAgreesWithTheDetectorsBearingModel) {
  CameraSimConfig c;
  c.mount = {15.0, 0.1, 0.2};
  CameraSim cam(c, world::World{});
  const core::NavPose pose{{3.0, -2.0}, 40.0};
  for (const double rel_deg : {-35.0, -10.0, 0.0, 22.0, 38.0}) {
    // A point 500 m away at camera height lies on the horizon row, at the bearing the
    // detectors' pinhole model gives back for its column.
    const core::NavPoint eye = core::body_to_nav(pose, {c.mount.x_m, c.mount.y_m});
    const double b = core::deg_to_rad(pose.heading_deg + c.mount.yaw_deg + rel_deg);
    const core::NavPoint far{eye.north_m + 500.0 * std::cos(b), eye.east_m + 500.0 * std::sin(b)};
    cv::Point2d px;
    ASSERT_TRUE(cam.project(pose, far, c.height_m, px));
    EXPECT_NEAR(px.y, 240.0, 1e-6);
    EXPECT_NEAR(perception::camera_bearing_deg(px.x, c.width_px, c.hfov_deg), rel_deg, 1e-6);
    EXPECT_NEAR(perception::body_bearing_deg(px.x, c.width_px, c.hfov_deg, c.mount.yaw_deg),
                rel_deg + c.mount.yaw_deg, 1e-6);
    EXPECT_NEAR(cam.bearing_in_image_deg(pose, far), rel_deg, 1e-6);
  }
  // Tilting the camera down raises the horizon.
  c.tilt_down_deg = 10.0;
  CameraSim tilted(c, world::World{});
  cv::Point2d px;
  ASSERT_TRUE(tilted.project(pose, {pose.position.north_m + 1000.0, pose.position.east_m + 1000.0},
                             c.height_m, px));
  EXPECT_NEAR(px.y, 240.0 - tilted.focal_px() * std::tan(core::deg_to_rad(10.0)), 0.2);
}

TEST(CameraSim, FramesAtItsRate) {
  CameraSimConfig c = plain_config();
  c.rate_hz = 15.0;
  CameraSim cam(c, world::World{});
  cv::Mat frame;
  int frames = 0;
  for (core::TimeNs t = 0; t < core::sec_to_ns(2.0); t += core::ms_to_ns(10)) {
    if (cam.update(t, {{0.0, 0.0}, 0.0}, frame)) ++frames;
  }
  EXPECT_EQ(frames, 30);
}

TEST(CameraSim, HarbourSeaIsBlueGreenAndEveryVenueStillShowsItsMarker) {
  const core::NavPose pose{{0.0, 0.0}, 0.0};
  const world::World w = dock_world(5.0, 0.0, msg::Colour::kBlue, msg::Shape::kCross);
  CameraSimConfig c = plain_config();
  c.venue = Venue::kHarbour;
  CameraSim cam(c, w);
  cv::Mat frame;
  cam.render(pose, frame);
  // The water below the placard: hue about 97 (OpenCV), saturated: inside the default blue box.
  cv::Mat hsv;
  cv::cvtColor(frame(cv::Rect(20, 400, 600, 60)), hsv, cv::COLOR_BGR2HSV);
  const cv::Scalar mean = cv::mean(hsv);
  EXPECT_NEAR(mean[0], 97.0, 6.0);
  EXPECT_GT(mean[1], 110.0);
  // The label box of the glyph is where the detector finds it, at every venue.
  const auto box = cam.marker_box(pose, w.docks[0].marker);
  ASSERT_TRUE(box.has_value());
  for (const Venue v : {Venue::kPool, Venue::kHarbour, Venue::kOvercast, Venue::kLowSun}) {
    CameraSimConfig cv_config = plain_config();
    cv_config.venue = v;
    CameraSim venue_cam(cv_config, w);
    venue_cam.render(pose, frame);
    perception::MarkerDetector detector;
    msg::CameraDetections out;
    ASSERT_TRUE(detector.detect(frame, 0, out));
    const auto hit = perception::find_target(out, msg::Colour::kBlue, msg::Shape::kCross);
    ASSERT_TRUE(hit.has_value()) << venue_name(v);
    EXPECT_TRUE(box->contains(cv::Point2d(hit->center_x_px, hit->center_y_px))) << venue_name(v);
  }
  EXPECT_EQ(parse_venue("low_sun"), Venue::kLowSun);
  EXPECT_FALSE(parse_venue("lake").has_value());
}

}  // namespace
}  // namespace coxswain::sim::sensors
