// SPDX-License-Identifier: Apache-2.0
#pragma once
// Helpers shared by the u-blox codec tests: hex vectors, hand-built frames and a decode loop that
// records every produced message in a comparable form.
#include <cstdint>
#include <cstdio>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "coxswain/drivers/ublox/codec.hpp"
#include "coxswain/drivers/ublox/config.hpp"

namespace coxswain::drivers::ublox::test {

inline std::vector<std::uint8_t> from_hex(std::string_view hex) {
  std::vector<std::uint8_t> out;
  auto nibble = [](char c) -> int {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
  };
  int hi = -1;
  for (const char c : hex) {
    const int v = nibble(c);
    if (v < 0) continue;  // spaces allowed
    if (hi < 0) {
      hi = v;
    } else {
      out.push_back(static_cast<std::uint8_t>(hi * 16 + v));
      hi = -1;
    }
  }
  return out;
}

inline void append(std::vector<std::uint8_t>& dst, std::span<const std::uint8_t> src) {
  dst.insert(dst.end(), src.begin(), src.end());
}

/// "$<body>*hh\r\n" with the XOR checksum computed here.
inline std::string nmea(std::string_view body) {
  unsigned x = 0;
  for (const char c : body) x ^= static_cast<unsigned char>(c);
  char tail[8];
  std::snprintf(tail, sizeof tail, "*%02X\r\n", x);
  return "$" + std::string(body) + tail;
}

inline void append(std::vector<std::uint8_t>& dst, std::string_view text) {
  dst.insert(dst.end(), text.begin(), text.end());
}

inline void put_le(std::vector<std::uint8_t>& p, std::size_t off, std::int64_t v, int n) {
  for (int i = 0; i < n; ++i) {
    p[off + static_cast<std::size_t>(i)] =
        static_cast<std::uint8_t>((static_cast<std::uint64_t>(v) >> (8 * i)) & 0xFFU);
  }
}

/// Fields of a hand-built NAV-PVT (units as in the payload: 1e-7 deg, mm, mm/s, 1e-5 deg).
struct PvtSpec {
  std::uint32_t itow_ms = 100'000;
  int year = 2024, month = 5, day = 17, hour = 3, minute = 4, second = 5;
  std::int32_t nano = 250'000'000;
  std::uint8_t valid = 0x37;
  std::uint8_t fix_type = 3;
  std::uint8_t flags = 0x01;
  std::uint8_t num_sv = 20;
  std::int32_t lon_e7 = 1'268'000'000;  // 126.8 E
  std::int32_t lat_e7 = 351'000'000;    // 35.1 N
  std::int32_t hmsl_mm = 12'345;
  std::uint32_t hacc_mm = 14, vacc_mm = 21;
  std::int32_t vel_n = 1500, vel_e = -2000, vel_d = 30, gspeed = 2500;
  std::int32_t head_mot_e5 = 30'687'000;  // 306.87 deg
};

inline UbxFrame nav_pvt_frame(const PvtSpec& s) {
  std::vector<std::uint8_t> p(92, 0);
  put_le(p, 0, s.itow_ms, 4);
  put_le(p, 4, s.year, 2);
  p[6] = static_cast<std::uint8_t>(s.month);
  p[7] = static_cast<std::uint8_t>(s.day);
  p[8] = static_cast<std::uint8_t>(s.hour);
  p[9] = static_cast<std::uint8_t>(s.minute);
  p[10] = static_cast<std::uint8_t>(s.second);
  p[11] = s.valid;
  put_le(p, 16, s.nano, 4);
  p[20] = s.fix_type;
  p[21] = s.flags;
  p[23] = s.num_sv;
  put_le(p, 24, s.lon_e7, 4);
  put_le(p, 28, s.lat_e7, 4);
  put_le(p, 32, s.hmsl_mm + 20'000, 4);
  put_le(p, 36, s.hmsl_mm, 4);
  put_le(p, 40, s.hacc_mm, 4);
  put_le(p, 44, s.vacc_mm, 4);
  put_le(p, 48, s.vel_n, 4);
  put_le(p, 52, s.vel_e, 4);
  put_le(p, 56, s.vel_d, 4);
  put_le(p, 60, s.gspeed, 4);
  put_le(p, 64, s.head_mot_e5, 4);
  return make_ubx_frame(kNavPvt, p);
}

/// A comparable record of one produced message (views copied out).
struct Record {
  MessageKind kind = MessageKind::kNone;
  msg::GnssFix fix;
  HpPosLlh hp;
  UbxId ubx;
  std::uint16_t rtcm_type = 0;
  std::vector<std::uint8_t> rtcm_bytes;
  std::string nmea_address;

  bool operator==(const Record& o) const {
    return kind == o.kind && fix.lat_deg == o.fix.lat_deg && fix.lon_deg == o.fix.lon_deg &&
           fix.utc_ns == o.fix.utc_ns && fix.itow_ms == o.fix.itow_ms && fix.rtk == o.fix.rtk &&
           fix.fix_type == o.fix.fix_type && fix.ground_speed_mps == o.fix.ground_speed_mps &&
           hp.lat_deg == o.hp.lat_deg && ubx == o.ubx && rtcm_type == o.rtcm_type &&
           rtcm_bytes == o.rtcm_bytes && nmea_address == o.nmea_address;
  }
};

inline Record record(const Message& m) {
  Record r;
  r.kind = m.kind;
  if (m.kind == MessageKind::kFix) r.fix = m.fix;
  if (m.kind == MessageKind::kHpPosLlh) r.hp = m.hp;
  if (m.kind == MessageKind::kAck || m.kind == MessageKind::kNak ||
      m.kind == MessageKind::kOtherUbx) {
    r.ubx = m.ubx;
  }
  if (m.kind == MessageKind::kRtcm3) {
    r.rtcm_type = m.rtcm3.message_type;
    r.rtcm_bytes.assign(m.rtcm3.bytes.begin(), m.rtcm3.bytes.end());
  }
  r.nmea_address = std::string(m.nmea_address);
  return r;
}

/// Feeds `bytes` in chunks of `chunk` bytes (0 = all at once) through the canonical codec loop,
/// then drains frames still buffered, and returns every produced message.
inline std::vector<Record> decode_all(Decoder& d, std::span<const std::uint8_t> bytes,
                                      std::size_t chunk = 0) {
  std::vector<Record> out;
  if (chunk == 0) chunk = bytes.size() == 0 ? 1 : bytes.size();
  for (std::size_t off = 0; off < bytes.size(); off += chunk) {
    std::span<const std::uint8_t> rest = bytes.subspan(off, std::min(chunk, bytes.size() - off));
    while (!rest.empty()) {
      const DecodeStep step = d.decode(rest);
      if (step.consumed == 0) throw std::runtime_error("decoder consumed nothing");
      rest = rest.subspan(step.consumed);
      if (step.produced) out.push_back(record(d.message()));
    }
  }
  while (true) {
    const DecodeStep step = d.decode({});
    if (!step.produced) break;
    out.push_back(record(d.message()));
  }
  return out;
}

}  // namespace coxswain::drivers::ublox::test
