// SPDX-License-Identifier: Apache-2.0
#pragma once
// How to reach the hardware (devices.yaml): serial paths and rates, the camera, the live
// interfaces. Plain data, no file format and no engine: each driver includes this alone.
#include <cstdint>
#include <string>
#include <vector>

namespace coxswain::config {

enum class LidarScanMode : std::uint8_t { kAuto = 0, kStandard, kExpress };
enum class GnssReceiver : std::uint8_t { kF9 = 0, kM8 };
enum class GnssPort : std::uint8_t { kUsb = 0, kUart1 };
enum class ImuOutput : std::uint8_t { kAscii = 0, kBinary };

struct SerialDeviceConfig {
  bool enabled = true;
  std::string path;
  std::uint32_t baud = 115200;
  std::uint32_t timeout_ms = 500;  // silence longer than this = stale
};

struct LidarDeviceConfig : SerialDeviceConfig {
  LidarDeviceConfig() {
    path = "/dev/ttyLiDAR";
    timeout_ms = 200;
  }
  LidarScanMode scan_mode = LidarScanMode::kAuto;
  std::uint16_t motor_pwm = 660;  // A2/A3 accessory board PWM
  std::uint16_t motor_rpm = 600;  // S-series
};

struct ImuDeviceConfig : SerialDeviceConfig {
  ImuDeviceConfig() {
    path = "/dev/ttyIMU";
    timeout_ms = 200;
  }
  ImuOutput output = ImuOutput::kAscii;
  double rate_hz = 100.0;
  double declination_deg = 0.0;  // magnetic declination at the site, east positive
  // Hard iron (board x forward, y starboard, microtesla) and the soft-iron map (row-major 2x2)
  // fitted from a slow turn in place (`coxswain calibrate mag`); zero/identity = uncalibrated.
  double mag_hard_iron_x_ut = 0.0;
  double mag_hard_iron_y_ut = 0.0;
  double mag_soft_iron_xx = 1.0;
  double mag_soft_iron_xy = 0.0;
  double mag_soft_iron_yx = 0.0;
  double mag_soft_iron_yy = 1.0;
};

struct GnssDeviceConfig : SerialDeviceConfig {
  GnssDeviceConfig() {
    path = "/dev/ttyGPS";
    baud = 38400;
    timeout_ms = 1500;
  }
  GnssReceiver receiver = GnssReceiver::kF9;
  GnssPort port = GnssPort::kUsb;
  double rate_hz = 5.0;
  bool nmea_output = false;
  std::string rtcm_input;  // "", a file or pipe path, or tcp://host:port
};

struct ArduinoDeviceConfig : SerialDeviceConfig {
  ArduinoDeviceConfig() { path = "/dev/ttyARDUINO"; }
  std::uint32_t failsafe_ms = 300;
};

struct CameraDeviceConfig {
  bool enabled = true;
  std::string source = "/dev/videoCAM";  // a V4L2 device, a video file or an image directory
  bool loop = true;  // video file / image directory: start again at the end (desk work)
  std::uint32_t width_px = 640;
  std::uint32_t height_px = 480;
  double fps = 30.0;
  double hfov_deg = 80.0;
  bool auto_exposure = false;
  double exposure = 100.0;
  double saturation = 128.0;
  double contrast = 128.0;
  double brightness = 128.0;
  std::uint32_t timeout_ms = 1000;
  /// Frames kept for the viewers (the recording's and the live view's /camera/image, JPEG):
  /// at most this often, scaled down to at most this width, at this JPEG quality.
  double image_rate_hz = 5.0;  // 0 = no images
  std::uint32_t image_max_width_px = 640;
  std::uint32_t image_jpeg_quality = 75;
};

/// The local control interface and live view (src/live): control socket, status page and the
/// Foxglove WebSocket server.
struct LiveConfig {
  std::string control_socket;  // "" = <run directory>/control.sock
  bool http_enabled = true;    // status page + Foxglove WebSocket
  std::string http_address = "127.0.0.1";
  std::uint16_t http_port = 8765;  // 0 = any free port (written to <run directory>/live.port)
  double viz_rate_hz = 10.0;       // Foxglove messageData per channel at most this often
  std::string token;               // status page buttons; "" = buttons refused
  // Host names besides IP literals and "localhost" that name this server (DNS-rebinding guard).
  std::vector<std::string> allowed_hosts;
  // Browser origins besides the server's own that may use it ("scheme://host[:port]").
  std::vector<std::string> allowed_origins = {"https://app.foxglove.dev"};
};

struct DevicesConfig {
  std::string file;
  LidarDeviceConfig lidar;
  ImuDeviceConfig imu;
  GnssDeviceConfig gnss;
  ArduinoDeviceConfig arduino;
  CameraDeviceConfig camera;
  LiveConfig live;
};

}  // namespace coxswain::config
