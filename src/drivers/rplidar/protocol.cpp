// SPDX-License-Identifier: Apache-2.0
#include "coxswain/drivers/rplidar/protocol.hpp"

#include <algorithm>

namespace coxswain::drivers::rplidar {
namespace {

// Writes "<letter><a>M<b>" into `name` (NUL-terminated, truncated to fit).
void write_name(std::array<char, 8>& name, char letter, unsigned a, unsigned b) {
  std::size_t i = 0;
  auto put = [&](char c) {
    if (i + 1 < name.size()) name[i++] = c;
  };
  auto put_num = [&](unsigned v) {
    if (v >= 10) put(static_cast<char>('0' + (v / 10) % 10));
    put(static_cast<char>('0' + v % 10));
  };
  put(letter);
  put_num(a);
  put('M');
  put_num(b);
  name[i] = '\0';
}

}  // namespace

ModelInfo model_info(const DeviceInfo& info) {
  ModelInfo m;
  const unsigned major = info.model_major();
  const unsigned minor = info.model_minor();
  const bool new_design = major >= 4;
  m.supports_conf = new_design || info.firmware() >= 0x0118;         // fw >= 1.24
  m.supports_sample_rate = new_design || info.firmware() >= 0x0111;  // fw >= 1.17
  if (major >= 1 && major <= 3) {
    m.family = Family::kA;
    write_name(m.name, 'A', major, minor);
    // The SDK guesses 256000 for A units with hardware >= 6 (A2M7/A2M12/A3), else 115200.
    m.native_baud = (major >= 2 && info.hardware >= 6) ? 256000U : 115200U;
    m.motor = major < 2 ? MotorControl::kDtr : MotorControl::kPwm;
    m.query_acc_board = major >= 2;
    // Datasheet ranges: A1 0.15-12 m, A2 0.2-12 m (A2M12/A2M7 16 m), A3 0.2-25 m.
    m.min_range_m = major == 1 ? 0.15F : 0.2F;
    m.max_range_m =
        major == 1 ? 12.0F : (major == 2 ? (info.hardware >= 6 ? 16.0F : 12.0F) : 25.0F);
  } else if (major >= 4 && major <= 5) {
    m.family = Family::kC;
    write_name(m.name, 'C', major - 3, minor);
    m.native_baud = 460800U;
    // The SDK takes the A2/A3 branch and queries the accessory board; a C1 answers "no PWM" and
    // spins under firmware control (docs/protocols.md 1.11, inferred).
    m.motor = MotorControl::kFirmware;
    m.query_acc_board = true;
    m.min_range_m = 0.05F;
    m.max_range_m = 12.0F;
  } else if (major >= 6 && major <= 8) {
    m.family = Family::kS;
    write_name(m.name, 'S', major - 5, minor);
    m.native_baud = major == 6 ? 256000U : (info.model == 0x82 ? 460800U : 1000000U);
    m.motor = MotorControl::kRpmCommand;
    m.min_range_m = major == 6 ? 0.1F : 0.05F;
    m.max_range_m = major == 7 ? 30.0F : 40.0F;
  } else if (major >= 9 && major <= 11) {
    m.family = Family::kT;
    write_name(m.name, 'T', major - 8, minor);
    m.motor = MotorControl::kFirmware;
    m.min_range_m = 0.05F;
    m.max_range_m = 40.0F;
  } else if (major >= 12) {
    m.family = Family::kM;
    write_name(m.name, 'M', major - 11, minor);
    m.motor = MotorControl::kFirmware;
    m.min_range_m = 0.05F;
    m.max_range_m = 40.0F;
  }
  return m;
}

std::uint32_t LidarConf::as_uint(std::size_t bytes) const {
  if (bytes > 4 || bytes > size) return 0;
  std::uint32_t v = 0;
  for (std::size_t i = 0; i < bytes; ++i) v |= static_cast<std::uint32_t>(data[i]) << (8 * i);
  return v;
}

std::string_view LidarConf::as_text() const {
  const auto* begin = reinterpret_cast<const char*>(data.data());
  const std::size_t n = std::min<std::size_t>(size, data.size());
  std::size_t len = 0;
  while (len < n && begin[len] != '\0') ++len;
  return {begin, len};
}

}  // namespace coxswain::drivers::rplidar
