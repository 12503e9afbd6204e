// SPDX-License-Identifier: Apache-2.0
#include "coxswain/app/calibrate_mag.hpp"

#include <array>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <vector>

#include "coxswain/guidance/mag_calibration.hpp"
#include "coxswain/msg/imu_sample.hpp"
#include "coxswain/record/bytes.hpp"
#include "coxswain/record/layouts.hpp"
#include "coxswain/record/mcap_reader.hpp"
#include "coxswain/record/proto_codec.hpp"

namespace coxswain::app {

std::string with_mag_calibration(const std::string& devices_yaml, const std::string& keys_block) {
  std::istringstream in(devices_yaml);
  std::string line;
  std::ostringstream out;
  bool in_imu = false;
  bool found = false;
  while (std::getline(in, line)) {
    const bool top_level = !line.empty() && line[0] != ' ' && line[0] != '#';
    if (top_level) in_imu = line.rfind("imu:", 0) == 0;
    if (in_imu && line.find("mag_hard_iron_") != std::string::npos) continue;
    if (in_imu && line.find("mag_soft_iron_") != std::string::npos) continue;
    out << line << '\n';
    if (top_level && in_imu) {
      out << keys_block;
      found = true;
    }
  }
  return found ? out.str() : std::string();
}

int calibrate_mag(const std::string& recording, const std::string& devices_file, std::ostream& out,
                  std::ostream& err) {
  record::McapReader reader;
  if (!reader.open(recording)) {
    err << "cannot read " << recording << "\n";
    return 1;
  }
  std::vector<std::array<double, 2>> samples;
  std::optional<std::uint16_t> imu_channel;
  const record::McapReadReport report = reader.read([&](const record::McapMessageView& m) {
    if (!imu_channel) imu_channel = reader.channel_id("/imu");
    if (!imu_channel || m.channel_id != *imu_channel) return;
    record::Encoding encoding = record::Encoding::kProtobuf;
    if (!record::encoding_of(reader.channels().at(*imu_channel).message_encoding, encoding)) {
      return;
    }
    std::uint64_t sequence = 0;
    msg::ImuSample s;
    if (!record::decode_sample(encoding, m.data, sequence, s) || !s.has_inertial) return;
    samples.push_back({s.mag_ut[0], s.mag_ut[1]});
  });
  if (!report.error.empty() && samples.empty()) {
    err << recording << ": " << report.error << "\n";
    return 1;
  }
  std::string why;
  const auto cal = guidance::fit_mag_calibration(samples, why);
  if (!cal) {
    err << recording << ": " << why << "\n";
    return 1;
  }
  char block[512];
  (void)std::snprintf(block, sizeof block,
                      "  mag_hard_iron_x_ut: %.4f   # coxswain calibrate mag: %zu samples, "
                      "%.0f deg of turn, residual %.3f uT\n"
                      "  mag_hard_iron_y_ut: %.4f\n"
                      "  mag_soft_iron_xx: %.6f\n  mag_soft_iron_xy: %.6f\n"
                      "  mag_soft_iron_yx: %.6f\n  mag_soft_iron_yy: %.6f\n",
                      cal->hard_iron_x_ut, cal->samples, cal->coverage_deg, cal->residual_rms_ut,
                      cal->hard_iron_y_ut, cal->soft_iron[0], cal->soft_iron[1], cal->soft_iron[2],
                      cal->soft_iron[3]);
  out << "imu:\n" << block;
  if (devices_file.empty()) return 0;
  std::ifstream f(devices_file);
  if (!f) {
    err << "cannot read " << devices_file << "\n";
    return 2;
  }
  std::stringstream text;
  text << f.rdbuf();
  const std::string updated = with_mag_calibration(text.str(), block);
  if (updated.empty()) {
    err << devices_file << " has no imu: section\n";
    return 2;
  }
  std::ofstream w(devices_file, std::ios::trunc);
  w << updated;
  if (!w) {
    err << "cannot write " << devices_file << "\n";
    return 2;
  }
  out << "written to " << devices_file << "\n";
  return 0;
}

}  // namespace coxswain::app
