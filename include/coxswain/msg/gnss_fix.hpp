// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>

#include "coxswain/core/time.hpp"

namespace coxswain::msg {

enum class FixType : std::uint8_t {
  kNoFix = 0,
  kDeadReckoning = 1,
  k2D = 2,
  k3D = 3,
  kGnssDeadReckoning = 4,
  kTimeOnly = 5,
};

/// Carrier-phase solution (UBX NAV-PVT carrSoln, NMEA GGA quality 5/4).
enum class RtkSolution : std::uint8_t { kNone = 0, kFloat = 1, kFixed = 2 };

/// kUbxNavLegacy: NAV-SOL / NAV-POSLLH / NAV-VELNED / NAV-STATUS / NAV-POSECEF of one epoch
/// (receivers and configurations without NAV-PVT, e.g. timing receivers).
enum class GnssSource : std::uint8_t {
  kUbxNavPvt = 0,
  kNmeaGga = 1,
  kNmeaRmc = 2,
  kNmeaGll = 3,
  kUbxNavLegacy = 4,
};

/// A position fix from the receiver, with the quality fields the mission needs to trust it.
struct GnssFix {
  core::TimeNs stamp_ns = core::kNeverNs;
  GnssSource source = GnssSource::kUbxNavPvt;
  FixType fix_type = FixType::kNoFix;
  bool fix_ok = false;     // gnssFixOK / GGA quality > 0 / RMC status A
  bool diff_soln = false;  // DGPS/SBAS corrections applied
  RtkSolution rtk = RtkSolution::kNone;
  double lat_deg = 0.0;
  double lon_deg = 0.0;
  double height_msl_m = 0.0;
  double h_acc_m = -1.0;  // < 0 = unknown (NMEA without GST)
  double v_acc_m = -1.0;
  double hdop = -1.0;
  std::uint8_t satellites = 0;
  bool velocity_valid = false;
  double vel_north_mps = 0.0;
  double vel_east_mps = 0.0;
  double vel_down_mps = 0.0;
  double ground_speed_mps = 0.0;
  double course_deg = 0.0;  // heading of motion, true, (-180, 180]
  double s_acc_mps = -1.0;  // speed accuracy estimate (UBX sAcc); < 0 = unknown
  /// UTC of the epoch as Unix nanoseconds; 0 when the receiver has no valid time.
  std::int64_t utc_ns = 0;
  std::uint32_t itow_ms = 0;  // GPS time of week of the epoch (UBX), groups one epoch

  /// True when this fix can be used for navigation.
  [[nodiscard]] bool usable() const {
    return fix_ok && (fix_type == FixType::k2D || fix_type == FixType::k3D ||
                      fix_type == FixType::kGnssDeadReckoning);
  }
};

}  // namespace coxswain::msg
