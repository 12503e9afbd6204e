// SPDX-License-Identifier: Apache-2.0
// `coxswain decode`'s library: captures built with the production encoders and the documented
// example lines decode into the expected JSON objects and error counters.
#include "coxswain/app/decode_capture.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "coxswain/drivers/arduino/wire.hpp"
#include "coxswain/drivers/rplidar/answer_encoder.hpp"
#include "coxswain/drivers/ublox/config.hpp"

namespace coxswain::app {
namespace {

using nlohmann::json;
using Bytes = std::vector<std::uint8_t>;

void append(Bytes& b, std::span<const std::uint8_t> more) {
  b.insert(b.end(), more.begin(), more.end());
}
void append(Bytes& b, std::string_view text) { b.insert(b.end(), text.begin(), text.end()); }

std::string nmea(std::string_view body) {
  unsigned x = 0;
  for (const char c : body) x ^= static_cast<unsigned char>(c);
  char tail[8];
  std::snprintf(tail, sizeof tail, "*%02X\r\n", x);
  return "$" + std::string(body) + tail;
}

struct Decoded {
  std::vector<json> messages;
  json summary;
};

// Feeds the capture in pieces of `piece` bytes (the output must not depend on the split).
Decoded decode(CaptureFormat format, const Bytes& bytes, std::size_t piece) {
  CaptureDecoder d(format);
  Decoded out;
  const auto emit = [&](const json& j) { out.messages.push_back(j); };
  for (std::size_t at = 0; at < bytes.size(); at += piece) {
    d.feed(std::span<const std::uint8_t>(bytes).subspan(at, std::min(piece, bytes.size() - at)),
           emit);
  }
  d.finish(emit);
  out.summary = d.summary();
  return out;
}

Decoded decode_both_ways(CaptureFormat format, const Bytes& bytes) {
  const Decoded whole = decode(format, bytes, bytes.size());
  const Decoded bytewise = decode(format, bytes, 1);
  EXPECT_EQ(whole.messages, bytewise.messages);
  EXPECT_EQ(whole.summary, bytewise.summary);
  return whole;
}

TEST(DecodeCapture, FormatNames) {
  for (const auto f : {CaptureFormat::kRplidar, CaptureFormat::kMyahrs, CaptureFormat::kUblox,
                       CaptureFormat::kArduino}) {
    EXPECT_EQ(parse_capture_format(capture_format_name(f)), f);
  }
  EXPECT_FALSE(parse_capture_format("lidar").has_value());
}

TEST(DecodeCapture, UbloxFixesAcksAndErrors) {
  Bytes b;
  append(b, "\x01\x02junk");
  const std::string gga =
      nmea("GNGGA,123519.00,3507.12345,N,12648.00000,E,4,18,0.55,12.3,M,20.1,M,1.0,0000");
  append(b, gga);
  const std::array<std::uint8_t, 2> acked{0x06, 0x8A};
  const auto ack = drivers::ublox::make_ubx_frame({0x05, 0x01}, acked);
  append(b, ack.bytes());
  std::string bad =
      nmea("GNGGA,123520.00,3507.12345,N,12648.00000,E,4,18,0.55,12.3,M,20.1,M,1.0,0000");
  bad[bad.size() - 3] = bad[bad.size() - 3] == '0' ? '1' : '0';  // wrong checksum digit
  append(b, bad);

  const Decoded d = decode_both_ways(CaptureFormat::kUblox, b);
  ASSERT_EQ(d.messages.size(), 2U);
  const json& fix = d.messages[0];
  EXPECT_EQ(fix["type"], "fix");
  EXPECT_EQ(fix["source"], "nmea_gga");
  EXPECT_EQ(fix["rtk"], "fixed");  // GGA quality 4
  EXPECT_NEAR(fix["lat_deg"].get<double>(), 35.0 + 7.12345 / 60.0, 1e-9);
  EXPECT_NEAR(fix["lon_deg"].get<double>(), 126.8, 1e-9);
  EXPECT_EQ(fix["satellites"], 18);
  EXPECT_EQ(d.messages[1]["type"], "ack");
  EXPECT_EQ(d.messages[1]["class"], "0x06");
  EXPECT_EQ(d.messages[1]["id"], "0x8A");
  EXPECT_EQ(d.messages[0]["end_offset_bytes"], 6 + gga.size());
  EXPECT_EQ(d.messages[1]["end_offset_bytes"], 6 + gga.size() + ack.size);
  EXPECT_EQ(d.summary["summary"], true);
  EXPECT_EQ(d.summary["device"], "ublox");
  EXPECT_EQ(d.summary["messages"], 2);
  EXPECT_EQ(d.summary["bytes"], b.size());
  EXPECT_EQ(d.summary["codec"]["checksum_errors"], 1);
  EXPECT_GE(d.summary["codec"]["bytes_skipped"].get<int>(), 6);
}

TEST(DecodeCapture, MyahrsSamplesAndResponses) {
  Bytes b;
  // The example sentence of docs/protocols.md 2.4 and a response.
  append(b,
         "$RPYIMU,15,-1.55,-1.25,97.31,-0.0142,-0.0010,-0.9224,-0.9756,-0.3659,-0.8537,-8.4000,"
         "-46.8000,5.4000,38.3*36\r\n");
  append(b, "$RPY,04,-1.55,-1.25,96.94*51\r\n");  // checksum off by one: rejected
  std::string response = "~divider,OK";
  unsigned x = 0;
  for (const char c : response) x ^= static_cast<unsigned char>(c);
  char tail[8];
  std::snprintf(tail, sizeof tail, "*%02X\r\n", x);
  append(b, response + tail);

  const Decoded d = decode_both_ways(CaptureFormat::kMyahrs, b);
  ASSERT_EQ(d.messages.size(), 2U);
  const json& s = d.messages[0];
  EXPECT_EQ(s["type"], "sample");
  EXPECT_EQ(s["sequence"], 15);
  EXPECT_DOUBLE_EQ(s["yaw_magnetic_deg"].get<double>(), 97.31);
  EXPECT_DOUBLE_EQ(s["roll_deg"].get<double>(), -1.55);
  EXPECT_DOUBLE_EQ(s["accel_g"][2].get<double>(), -0.9224);
  EXPECT_DOUBLE_EQ(s["temperature_c"].get<double>(), 38.3);
  EXPECT_EQ(d.messages[1]["type"], "response");
  EXPECT_EQ(d.messages[1]["command"], "divider");
  EXPECT_EQ(d.messages[1]["ok"], true);
  EXPECT_EQ(d.summary["codec"]["ascii_checksum_errors"], 1);
  EXPECT_EQ(d.summary["messages"], 2);
}

TEST(DecodeCapture, RplidarFollowsTheDescriptorsInTheStream) {
  using namespace drivers::rplidar;
  Bytes b;
  append(b, "\x55\xAA");  // noise before the first descriptor
  DeviceInfo info;
  info.model = 0x18;
  info.firmware_major = 1;
  info.firmware_minor = 29;
  info.hardware = 7;
  append(b, encode_descriptor(AnswerType::kDevInfo));
  append(b, encode_device_info(info));
  append(b, encode_descriptor(AnswerType::kHealth));
  append(b, encode_health(Health{}));
  append(b, encode_descriptor(AnswerType::kMeasurement));
  append(b, encode_standard_node(true, 15, 90 * 64, 4000));    // 90 deg, 1000 mm
  append(b, encode_standard_node(false, 15, 180 * 64, 8000));  // 180 deg, 2000 mm
  auto broken = encode_standard_node(false, 15, 270 * 64, 400);
  broken[0] |= 0x03U;  // S and !S both set: fails the node check
  append(b, broken);

  const Decoded d = decode_both_ways(CaptureFormat::kRplidar, b);
  ASSERT_GE(d.messages.size(), 4U);
  EXPECT_EQ(d.messages[0]["type"], "device_info");
  EXPECT_EQ(d.messages[0]["firmware_minor"], 29);
  EXPECT_EQ(d.messages[1]["type"], "health");
  EXPECT_EQ(d.messages[1]["status"], 0);
  EXPECT_EQ(d.messages[2]["type"], "nodes");
  EXPECT_EQ(d.messages[2]["answer_type"], "0x81");
  EXPECT_NEAR(d.messages[2]["nodes"][0]["angle_deg"].get<double>(), 90.0, 0.05);
  EXPECT_DOUBLE_EQ(d.messages[2]["nodes"][0]["distance_mm"].get<double>(), 1000.0);
  EXPECT_EQ(d.messages[2]["nodes"][0]["start_of_scan"], true);
  EXPECT_DOUBLE_EQ(d.messages[3]["nodes"][0]["distance_mm"].get<double>(), 2000.0);
  EXPECT_EQ(d.summary["codec"]["descriptors"], 3);
  EXPECT_GE(d.summary["codec"]["node_check_errors"].get<int>(), 1);
  EXPECT_GE(d.summary["codec"]["bytes_skipped"].get<int>(), 2);
}

TEST(DecodeCapture, RplidarWithoutADescriptorDecodesNothing) {
  using namespace drivers::rplidar;
  Bytes b;
  for (int i = 0; i < 10; ++i)
    append(b, encode_standard_node(i == 0, 15, static_cast<std::uint16_t>(64 * 10 * i), 4000));
  const Decoded d = decode_both_ways(CaptureFormat::kRplidar, b);
  EXPECT_TRUE(d.messages.empty());
  EXPECT_EQ(d.summary["codec"]["descriptors"], 0);
}

TEST(DecodeCapture, ArduinoBoardMessages) {
  using namespace drivers::arduino;
  Bytes b;
  std::array<std::uint8_t, kMaxFrame> buf{};
  Ready ready{};
  ready.protocol_version = 1;
  ready.fw_major = 1;
  ready.fw_minor = 2;
  ready.fw_patch = 3;
  ready.failsafe_ms = 300;
  ready.neutral_us[0] = 1500;
  ready.neutral_us[1] = 1500;
  append(b, std::span<const std::uint8_t>(buf.data(), encode(ready, 1, buf.data(), buf.size())));
  Telemetry tel{};
  tel.uptime_ms = 12345;
  tel.applied_pulse_us[0] = 1600;
  tel.applied_pulse_us[1] = 1450;
  tel.supply_mv = 12100;
  const std::size_t n = encode(tel, 2, buf.data(), buf.size());
  append(b, std::span<const std::uint8_t>(buf.data(), n));
  Bytes corrupt(buf.begin(), buf.begin() + static_cast<std::ptrdiff_t>(n));
  corrupt[n / 2] ^= 0x40U;
  append(b, corrupt);

  const Decoded d = decode_both_ways(CaptureFormat::kArduino, b);
  ASSERT_EQ(d.messages.size(), 2U);
  EXPECT_EQ(d.messages[0]["type"], "ready");
  EXPECT_EQ(d.messages[0]["firmware"], "1.2.3");
  EXPECT_EQ(d.messages[0]["failsafe_ms"], 300);
  EXPECT_EQ(d.messages[1]["type"], "telemetry");
  EXPECT_EQ(d.messages[1]["uptime_ms"], 12345);
  EXPECT_EQ(d.messages[1]["applied_pulse_us"], json::array({1600, 1450}));
  EXPECT_EQ(d.messages[1]["supply_mv"], 12100);
  EXPECT_EQ(d.summary["codec"]["checksum_errors"], 1);
}

TEST(DecodeCapture, FilePrintsJsonLinesThenSummary) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("coxswain_decode_test_" + std::to_string(::getpid()) + ".raw");
  {
    std::ofstream f(path, std::ios::binary);
    f << nmea("GNGGA,123519.00,3507.12345,N,12648.00000,E,1,08,1.0,5.0,M,20.0,M,,");
    f << nmea("GNGGA,123520.00,3507.12345,N,12648.00000,E,1,08,1.0,5.0,M,20.0,M,,");
  }
  std::ostringstream out;
  std::ostringstream err;
  ASSERT_EQ(decode_capture_file(CaptureFormat::kUblox, path, out, err), 0) << err.str();
  std::filesystem::remove(path);
  std::istringstream lines(out.str());
  std::vector<json> parsed;
  for (std::string line; std::getline(lines, line);) parsed.push_back(json::parse(line));
  ASSERT_EQ(parsed.size(), 3U);
  EXPECT_EQ(parsed[0]["type"], "fix");
  EXPECT_EQ(parsed[1]["type"], "fix");
  EXPECT_EQ(parsed[2]["summary"], true);
  EXPECT_EQ(parsed[2]["messages"], 2);
  EXPECT_TRUE(err.str().empty());

  std::ostringstream out2;
  std::ostringstream err2;
  EXPECT_EQ(decode_capture_file(CaptureFormat::kUblox, path, out2, err2), 1);
  EXPECT_NE(err2.str().find("cannot open"), std::string::npos);
  EXPECT_TRUE(out2.str().empty());
}

}  // namespace
}  // namespace coxswain::app
