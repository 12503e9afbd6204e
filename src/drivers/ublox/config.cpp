// SPDX-License-Identifier: Apache-2.0
#include "coxswain/drivers/ublox/config.hpp"

#include <cmath>
#include <cstring>

namespace coxswain::drivers::ublox {
namespace {

// NMEA-standard message ids in UBX class 0xF0 (for legacy CFG-MSG).
constexpr UbxId kNmeaGga{0xF0, 0x00};
constexpr UbxId kNmeaGll{0xF0, 0x01};
constexpr UbxId kNmeaGsa{0xF0, 0x02};
constexpr UbxId kNmeaGsv{0xF0, 0x03};
constexpr UbxId kNmeaRmc{0xF0, 0x04};
constexpr UbxId kNmeaVtg{0xF0, 0x05};

void put_u2(std::uint8_t* p, std::uint16_t v) {
  p[0] = static_cast<std::uint8_t>(v & 0xFFU);
  p[1] = static_cast<std::uint8_t>(v >> 8);
}

UbxFrame single_key(std::uint32_t key_id, std::uint64_t value) {
  ValsetBuilder b;
  if (!b.add(key_id, value)) return UbxFrame{};
  return b.build();
}

}  // namespace

UbxFrame make_ubx_frame(UbxId id, std::span<const std::uint8_t> payload) {
  UbxFrame f;
  if (payload.size() + 8 > f.data.size()) return f;
  f.data[0] = kUbxSync1;
  f.data[1] = kUbxSync2;
  f.data[2] = id.msg_class;
  f.data[3] = id.msg_id;
  put_u2(&f.data[4], static_cast<std::uint16_t>(payload.size()));
  if (!payload.empty()) std::memcpy(&f.data[6], payload.data(), payload.size());
  const auto ck = ubx_checksum(std::span<const std::uint8_t>(&f.data[2], payload.size() + 4));
  f.data[6 + payload.size()] = ck[0];
  f.data[7 + payload.size()] = ck[1];
  f.size = payload.size() + 8;
  return f;
}

std::size_t valset_value_size(std::uint32_t key_id) {
  switch ((key_id >> 28) & 0x07U) {
    case 1:
    case 2:
      return 1;
    case 3:
      return 2;
    case 4:
      return 4;
    case 5:
      return 8;
    default:
      return 0;
  }
}

ValsetBuilder::ValsetBuilder(std::uint8_t layers) {
  payload_[0] = 0;  // version 0: no transaction
  payload_[1] = layers;
  payload_[2] = 0;
  payload_[3] = 0;
}

bool ValsetBuilder::add(std::uint32_t key_id, std::uint64_t value) {
  const std::size_t n = valset_value_size(key_id);
  if (n == 0 || size_ + 4 + n > payload_.size()) return false;
  const bool is_bit = ((key_id >> 28) & 0x07U) == 1;
  if (is_bit ? value > 1 : (n < 8 && value >= (std::uint64_t{1} << (8 * n)))) return false;
  for (std::size_t i = 0; i < 4; ++i) {
    payload_[size_ + i] = static_cast<std::uint8_t>((key_id >> (8 * i)) & 0xFFU);
  }
  for (std::size_t i = 0; i < n; ++i) {
    payload_[size_ + 4 + i] = static_cast<std::uint8_t>((value >> (8 * i)) & 0xFFU);
  }
  size_ += 4 + n;
  return true;
}

UbxFrame ValsetBuilder::build() const {
  return make_ubx_frame(kCfgValset, std::span<const std::uint8_t>(payload_.data(), size_));
}

UbxFrame f9_set_meas_period(std::uint16_t period_ms) {
  return single_key(key::kRateMeas, period_ms);
}

UbxFrame f9_set_nav_pvt_output(Port port, std::uint8_t every_n) {
  return single_key(port == Port::kUsb ? key::kMsgoutNavPvtUsb : key::kMsgoutNavPvtUart1, every_n);
}

UbxFrame f9_set_dyn_model(std::uint8_t model) { return single_key(key::kNavspgDynModel, model); }

UbxFrame f9_set_output_protocols(Port port, bool nmea_enabled) {
  const bool usb = port == Port::kUsb;
  ValsetBuilder b;
  bool ok = b.add(usb ? key::kUsbOutProtUbx : key::kUart1OutProtUbx, 1) &&
            b.add(usb ? key::kUsbOutProtNmea : key::kUart1OutProtNmea, nmea_enabled ? 1 : 0);
  if (nmea_enabled) {
    ok = ok && b.add(usb ? key::kMsgoutNmeaGgaUsb : key::kMsgoutNmeaGgaUart1, 1) &&
         b.add(usb ? key::kMsgoutNmeaRmcUsb : key::kMsgoutNmeaRmcUart1, 1);
  }
  return ok ? b.build() : UbxFrame{};
}

UbxFrame m8_set_msg_rate(UbxId id, std::uint8_t every_n) {
  const std::array<std::uint8_t, 3> p{id.msg_class, id.msg_id, every_n};
  return make_ubx_frame(kCfgMsg, p);
}

UbxFrame m8_set_rate(std::uint16_t meas_period_ms, std::uint8_t time_ref) {
  std::array<std::uint8_t, 6> p{};
  put_u2(&p[0], meas_period_ms);
  put_u2(&p[2], 1);
  put_u2(&p[4], time_ref);
  return make_ubx_frame(kCfgRate, p);
}

UbxFrame m8_set_dyn_model(std::uint8_t model) {
  std::array<std::uint8_t, 36> p{};
  put_u2(&p[0], 0x0001);  // mask: apply dynModel only
  p[2] = model;
  return make_ubx_frame(kCfgNav5, p);
}

std::optional<std::string> ConfigParams::validate(Generation gen) const {
  const double max_hz = gen == Generation::kM8 ? 10.0 : 20.0;
  if (!std::isfinite(rate_hz) || rate_hz < 0.1 || rate_hz > max_hz) {
    return gen == Generation::kM8 ? "rate_hz must be in [0.1, 10] for an M8 receiver"
                                  : "rate_hz must be in [0.1, 20] for an F9 receiver";
  }
  if (port != Port::kUsb && port != Port::kUart1) return "port must be usb or uart1";
  return std::nullopt;
}

std::uint16_t ConfigParams::meas_period_ms() const {
  return static_cast<std::uint16_t>(std::lround(1000.0 / rate_hz));
}

ConfigPlan make_config_plan(Generation gen, const ConfigParams& params) {
  ConfigPlan plan;
  if (params.validate(gen)) return plan;
  auto add = [&plan](UbxFrame frame, std::string_view what) {
    plan.steps[plan.count++] = ConfigStep{frame, frame.id(), what};
  };
  const std::uint16_t period_ms = params.meas_period_ms();
  if (gen == Generation::kF9) {
    add(f9_set_meas_period(period_ms), "CFG-VALSET rate");
    add(f9_set_dyn_model(kDynModelSea), "CFG-VALSET dynamic model sea");
    add(f9_set_output_protocols(params.port, params.nmea_enabled), "CFG-VALSET output protocols");
    add(f9_set_nav_pvt_output(params.port, 1), "CFG-VALSET NAV-PVT every epoch");
    return plan;
  }
  add(m8_set_rate(period_ms), "CFG-RATE");
  add(m8_set_dyn_model(kDynModelSea), "CFG-NAV5 dynamic model sea");
  add(m8_set_msg_rate(kNavPvt, 1), "CFG-MSG NAV-PVT every epoch");
  if (params.nmea_enabled) {
    add(m8_set_msg_rate(kNmeaGga, 1), "CFG-MSG NMEA GGA on");
    add(m8_set_msg_rate(kNmeaRmc, 1), "CFG-MSG NMEA RMC on");
  } else {
    for (const UbxId id : {kNmeaGga, kNmeaGll, kNmeaGsa, kNmeaGsv, kNmeaRmc, kNmeaVtg}) {
      add(m8_set_msg_rate(id, 0), "CFG-MSG NMEA sentence off");
    }
  }
  return plan;
}

}  // namespace coxswain::drivers::ublox
