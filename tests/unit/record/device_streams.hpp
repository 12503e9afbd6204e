// SPDX-License-Identifier: Apache-2.0
#pragma once
// Byte streams in each device's real protocol, built with the protocol encoders (or by hand for
// text protocols), for recordings whose raw channels the codecs must decode again. Shared by the
// recorder's unit tests and the integration recording writer.
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "coxswain/drivers/arduino/wire.hpp"
#include "coxswain/drivers/rplidar/answer_encoder.hpp"

namespace coxswain::record::test {

/// A SCAN answer: descriptor, then `revolutions` x `nodes` standard nodes sweeping 0..360 deg.
inline std::vector<std::uint8_t> lidar_stream(int revolutions, int nodes) {
  namespace rp = drivers::rplidar;
  std::vector<std::uint8_t> out;
  const auto desc = rp::encode_descriptor(rp::AnswerType::kMeasurement);
  out.insert(out.end(), desc.begin(), desc.end());
  for (int r = 0; r < revolutions; ++r) {
    for (int n = 0; n < nodes; ++n) {
      const auto angle_q6 = static_cast<std::uint16_t>(n * 360 * 64 / nodes);
      const auto node = rp::encode_standard_node(n == 0, 40, angle_q6,
                                                 static_cast<std::uint16_t>(4 * (1000 + n)));
      out.insert(out.end(), node.begin(), node.end());
    }
  }
  return out;
}

inline std::string with_nmea_checksum(const std::string& body) {  // body without '$' and '*'
  std::uint8_t x = 0;
  for (char c : body) x = static_cast<std::uint8_t>(x ^ static_cast<std::uint8_t>(c));
  char cs[8];
  std::snprintf(cs, sizeof cs, "*%02X\r\n", x);
  return "$" + body + cs;
}

/// `count` NMEA GGA sentences, one per second, each a fix.
inline std::vector<std::uint8_t> gnss_stream(int count) {
  std::string s;
  for (int i = 0; i < count; ++i) {
    char body[160];
    std::snprintf(body, sizeof body,
                  "GNGGA,1200%02d.00,3507.12345,N,12900.54321,E,1,12,0.8,10.5,M,20.1,M,,", i % 60);
    s += with_nmea_checksum(body);
  }
  return {s.begin(), s.end()};
}

/// `count` myAHRS+ `$RPY` sentences (checksum = XOR from '$' to before '*').
inline std::vector<std::uint8_t> imu_stream(int count) {
  std::string s;
  for (int i = 0; i < count; ++i) {
    char body[96];
    std::snprintf(body, sizeof body, "$RPY,%d,1.50,-2.25,%.2f", i % 256, -170.0 + i);
    std::uint8_t x = 0;
    for (const char* p = body; *p != '\0'; ++p)
      x = static_cast<std::uint8_t>(x ^ static_cast<std::uint8_t>(*p));
    char cs[8];
    std::snprintf(cs, sizeof cs, "*%02X\r\n", x);
    s += body;
    s += cs;
  }
  return {s.begin(), s.end()};
}

/// `count` Arduino telemetry frames.
inline std::vector<std::uint8_t> arduino_stream(int count) {
  namespace ard = drivers::arduino;
  std::vector<std::uint8_t> out;
  for (int i = 0; i < count; ++i) {
    ard::Telemetry t{};
    t.uptime_ms = static_cast<std::uint32_t>(i * 50);
    t.applied_pulse_us[0] = 1500;
    t.applied_pulse_us[1] = 1500;
    t.supply_mv = 12600;
    std::uint8_t buf[ard::kMaxFrame];
    const std::size_t n = ard::encode(t, static_cast<std::uint16_t>(i), buf, sizeof buf);
    out.insert(out.end(), buf, buf + n);
  }
  return out;
}

}  // namespace coxswain::record::test
