// SPDX-License-Identifier: Apache-2.0
#pragma once
// Pure u-blox receiver stream decoder (UBX + NMEA 0183 + RTCM 3 mixed in one byte stream) and a
// stand-alone RTCM 3 framer for forwarding corrections. Follows the codec convention of
// coxswain/drivers/codec.hpp. Protocol facts: docs/protocols.md section 3
// (UBX frame 3.2, NAV-PVT 3.3, NAV-HPPOSLLH 3.4, ACK 3.5, NMEA 3.8, RTCM 3 3.9, plan 3.10).
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

#include "coxswain/drivers/codec.hpp"
#include "coxswain/msg/gnss_fix.hpp"

namespace coxswain::drivers::ublox {

inline constexpr std::uint8_t kUbxSync1 = 0xB5;
inline constexpr std::uint8_t kUbxSync2 = 0x62;
inline constexpr std::uint8_t kRtcm3Preamble = 0xD3;

/// Largest frame (any protocol) the decoder buffers. Longer UBX frames (e.g. RXM-RAWX with more
/// than ~250 measurements) are treated as framing errors. RTCM 3 frames are at most 1029 bytes.
inline constexpr std::size_t kMaxFrameBytes = 8192;
/// NMEA 0183 allows 82 characters; u-blox proprietary $PUBX sentences are a little longer.
inline constexpr std::size_t kMaxNmeaBytes = 128;

/// 8-bit Fletcher checksum (CK_A, CK_B) over `bytes` (UBX: class, id, length, payload).
[[nodiscard]] std::array<std::uint8_t, 2> ubx_checksum(std::span<const std::uint8_t> bytes);
/// CRC-24Q (poly 0x1864CFB, init 0, no reflection, no final xor) as used by RTCM 3.
[[nodiscard]] std::uint32_t crc24q(std::span<const std::uint8_t> bytes);
/// Unix seconds of a proleptic-Gregorian UTC date at 00:00:00 (civil calendar, any year).
[[nodiscard]] std::int64_t unix_days_from_civil(int year, unsigned month, unsigned day);

enum class FrameKind : std::uint8_t { kUbx, kNmea, kRtcm3 };

/// Which protocols a FrameScanner hunts for.
struct ProtocolMask {
  bool ubx = true;
  bool nmea = true;
  bool rtcm3 = true;
};

/// Splits a byte stream into complete, checksum-valid frames of the enabled protocols.
/// Hunts for a start byte (B5 62 / '$' / D3), reads the length, waits for the whole frame and
/// validates its checksum before trusting it; on any failure drops one byte and hunts again in
/// the bytes it already holds. Fixed internal buffer, no allocation. Not thread-safe.
class FrameScanner {
 public:
  explicit FrameScanner(ProtocolMask mask = {}) : mask_(mask) {}

  /// Consumes bytes (>= 1 when `input` is non-empty) and returns at most one frame per call.
  /// After a resync the buffer may already hold further complete frames: they come out of the
  /// following calls, also with an empty `input`.
  [[nodiscard]] DecodeStep next(std::span<const std::uint8_t> input);
  /// The frame produced by the last call (whole frame incl. sync and checksum); valid until the
  /// next call.
  [[nodiscard]] std::span<const std::uint8_t> frame() const { return {buf_.data(), frame_len_}; }
  [[nodiscard]] FrameKind kind() const { return kind_; }
  [[nodiscard]] const CodecStats& stats() const { return stats_; }
  /// For the owning decoder, which adds its own counts (messages_out, unsupported, malformed).
  [[nodiscard]] CodecStats& mutable_stats() { return stats_; }
  /// Drops buffered bytes (e.g. after a reconnect); keeps the statistics.
  void reset() {
    len_ = 0;
    frame_len_ = 0;
  }

 private:
  enum class Verdict : std::uint8_t { kNeedMore, kBad, kBadChecksum, kComplete };
  [[nodiscard]] bool is_start(std::uint8_t b) const;
  [[nodiscard]] Verdict assess(std::size_t& need) const;
  void drop_front(std::size_t n);
  [[nodiscard]] DecodeStep finish(std::size_t taken, bool produced);

  ProtocolMask mask_;
  // +1: after producing a frame the scanner may take one more byte so that `consumed` >= 1.
  std::array<std::uint8_t, kMaxFrameBytes + 1> buf_{};
  std::size_t len_ = 0;
  std::size_t frame_len_ = 0;  // produced frame at buf_[0, frame_len_), erased on the next call
  FrameKind kind_ = FrameKind::kUbx;
  CodecStats stats_;
};

/// A UBX message class/id pair.
struct UbxId {
  std::uint8_t msg_class = 0;
  std::uint8_t msg_id = 0;
  friend bool operator==(const UbxId&, const UbxId&) = default;
};

/// UBX-NAV-HPPOSLLH (01 14): high-precision geodetic position.
struct HpPosLlh {
  std::uint32_t itow_ms = 0;
  bool invalid_llh = false;  // flags bit0 (newer firmware)
  double lat_deg = 0.0;
  double lon_deg = 0.0;
  double height_m = 0.0;      // above the ellipsoid
  double height_msl_m = 0.0;  // above mean sea level
  double h_acc_m = 0.0;
  double v_acc_m = 0.0;
};

/// One RTCM 3 frame (preamble, length, payload, CRC) as a view into the decoder's buffer.
struct Rtcm3Frame {
  std::uint16_t message_type = 0;  // first 12 bits of the payload, e.g. 1005, 1077
  std::span<const std::uint8_t> bytes;
};

enum class MessageKind : std::uint8_t {
  kNone,
  kFix,        // NAV-PVT, NMEA GGA, RMC or GLL, older NAV messages -> Message::fix
  kHpPosLlh,   // NAV-HPPOSLLH -> Message::hp
  kAck,        // ACK-ACK -> Message::ubx = acknowledged class/id
  kNak,        // ACK-NAK -> Message::ubx = rejected class/id
  kRtcm3,      // -> Message::rtcm3
  kOtherUbx,   // valid UBX frame of another kind -> Message::ubx = its class/id
  kOtherNmea,  // valid NMEA sentence of another kind -> Message::nmea_address
};

/// The decoder's output. Only the member named by `kind` is meaningful. Views (rtcm3.bytes,
/// nmea_address) point into the decoder and are valid until its next decode() call.
struct Message {
  MessageKind kind = MessageKind::kNone;
  msg::GnssFix fix;  // stamp_ns left as kNeverNs: the adapter stamps on arrival
  HpPosLlh hp;
  UbxId ubx;
  Rtcm3Frame rtcm3;
  std::string_view nmea_address;  // talker + type, e.g. "GNGSV" (also set for GGA/RMC fixes)
};

/// u-blox stream decoder. Feed any split of the receiver's bytes; get one Message per produced
/// step. NMEA fixes: RMC gives the date and velocity, GGA the quality (4 = RTK fixed,
/// 5 = float), altitude, satellites and HDOP; a GGA fix also carries the date and velocity of the
/// RMC of the same second when it came first (u-blox order), so a GGA fix alone is complete.
/// GLL gives a 2-D position-only fix (dated from the last RMC/ZDA).
/// Receivers without NAV-PVT: NAV-SOL, NAV-POSLLH, NAV-VELNED, NAV-STATUS and NAV-POSECEF of one
/// epoch (same iTOW) are merged into one fix (source kUbxNavLegacy); each of them that adds to
/// an epoch whose status and position are known produces the fix so far, so the last one of the
/// epoch is complete. Position from POSLLH, else from ECEF; velocity from VELNED, else from
/// NAV-SOL's ECEF velocity; UTC from NAV-SOL's week and iTOW less the leap seconds of the last
/// valid NAV-TIMEGPS (18 s until one is seen). Once a NAV-PVT has been seen, they give no fix.
/// Pure: no clock, no I/O, no allocation. Not thread-safe (one owner).
class Decoder {
 public:
  Decoder() = default;

  /// See coxswain/drivers/codec.hpp for the loop. decode({}) delivers frames still buffered
  /// after a resync; an adapter may call it until `produced` is false after each read.
  [[nodiscard]] DecodeStep decode(std::span<const std::uint8_t> input);
  [[nodiscard]] const Message& message() const { return msg_; }
  [[nodiscard]] const CodecStats& stats() const { return scanner_.stats(); }
  /// Forgets buffered bytes and the NMEA date/velocity context; keeps the statistics.
  void reset();

 private:
  [[nodiscard]] bool interpret(FrameKind kind, std::span<const std::uint8_t> frame);
  [[nodiscard]] bool interpret_ubx(std::span<const std::uint8_t> frame);
  [[nodiscard]] bool interpret_nmea(std::span<const std::uint8_t> frame);
  /// Days since 1970 for a UTC time of day, from the last date seen (midnight-safe).
  [[nodiscard]] std::int64_t date_for(std::int64_t tod_ms) const;

  FrameScanner scanner_;
  Message msg_;
  // NMEA context: the last date (from RMC or ZDA) and the last RMC's velocity.
  bool have_date_ = false;
  std::int64_t date_days_ = 0;    // days since 1970-01-01 of the last date seen
  std::int64_t date_tod_ms_ = 0;  // UTC time of day that date belongs to
  bool have_rmc_velocity_ = false;
  std::int64_t rmc_tod_ms_ = -1;
  double rmc_speed_mps_ = 0.0;
  bool rmc_course_valid_ = false;
  double rmc_course_deg_ = 0.0;

  // Older NAV messages of the current epoch.
  struct LegacyEpoch {
    bool active = false;
    std::uint32_t itow_ms = 0;
    bool have_status = false;
    std::uint8_t fix_type = 0;
    bool fix_ok = false;
    bool diff_soln = false;
    bool have_llh = false;
    double lat_deg = 0.0, lon_deg = 0.0, height_msl_m = 0.0, h_acc_m = -1.0, v_acc_m = -1.0;
    bool have_ecef = false;
    double ecef_m[3] = {0.0, 0.0, 0.0};
    double p_acc_m = -1.0;
    bool have_velned = false;
    double vel_ned_mps[3] = {0.0, 0.0, 0.0};
    double ground_speed_mps = 0.0, course_deg = 0.0;
    double s_acc_mps = -1.0;  // NAV-VELNED's or NAV-SOL's speed accuracy
    bool have_ecef_vel = false;
    double ecef_vel_mps[3] = {0.0, 0.0, 0.0};
    bool have_week = false;
    std::int32_t week = 0;
    std::int32_t ftow_ns = 0;
    std::uint8_t satellites = 0;
    bool sol_emitted = false;
  };
  [[nodiscard]] LegacyEpoch& legacy_epoch(std::uint32_t itow_ms);
  [[nodiscard]] bool emit_legacy();
  [[nodiscard]] bool used_ubx(UbxId id);
  LegacyEpoch legacy_;
  std::int32_t leap_seconds_ = 18;
  bool pvt_seen_ = false;  // since the last reset(): the older messages are then ignored
};

/// Splits a correction stream (file, pipe, NTRIP/TCP) into complete CRC-checked RTCM 3 frames,
/// dropping anything else. Same loop as a codec; frame() is valid until the next call.
/// Not thread-safe.
class Rtcm3Framer {
 public:
  Rtcm3Framer() : scanner_(ProtocolMask{.ubx = false, .nmea = false, .rtcm3 = true}) {}

  [[nodiscard]] DecodeStep decode(std::span<const std::uint8_t> input);
  /// The last produced frame; forward these bytes unchanged to the receiver.
  [[nodiscard]] const Rtcm3Frame& frame() const { return frame_; }
  [[nodiscard]] const CodecStats& stats() const { return scanner_.stats(); }
  void reset() { scanner_.reset(); }

 private:
  FrameScanner scanner_;
  Rtcm3Frame frame_;
};

/// Message number of an RTCM 3 frame (first 12 payload bits), 0 if the payload is too short.
[[nodiscard]] std::uint16_t rtcm3_message_type(std::span<const std::uint8_t> frame);

}  // namespace coxswain::drivers::ublox
