// SPDX-License-Identifier: Apache-2.0
#pragma once
// Simulated u-blox receiver: one msg::GnssFix per epoch at rate_hz, from the true antenna position
// (mount from boat.yaml) plus a slowly wandering bias (the documents saw every point shifted 5-10 m
// one way), white noise and occasional loss of fix; or RTK float/fixed with centimetre noise.
// Fills every field the UBX NAV-PVT decoder fills. Deterministic for a seed. Not thread-safe.
#include <cstdint>
#include <optional>
#include <string>

#include "coxswain/core/frames.hpp"
#include "coxswain/core/geodesy.hpp"
#include "coxswain/core/time.hpp"
#include "coxswain/msg/gnss_fix.hpp"
#include "sim/rng/rng.hpp"
#include "sim/sensors/truth.hpp"

namespace coxswain::sim::sensors {

enum class RtkMode : std::uint8_t { kOff = 0, kFloat, kFixed };

struct GnssSimConfig {
  double rate_hz = 5.0;
  core::MountTransform mount{0.0, -0.6, 0.0};  // antenna (boat.yaml mounts.gnss)
  double antenna_height_m = 0.5;               // above the water, added to the height
  // Bias: a constant offset of bias_mean_m towards bias_direction_deg (navigation bearing) plus a
  // first-order Gauss-Markov wander per axis (stationary sigma, correlation time), its total
  // magnitude clamped to bias_max_m.
  double bias_mean_m = 6.0;
  double bias_direction_deg = 60.0;
  double bias_wander_sigma_m = 1.0;
  double bias_tau_s = 300.0;
  double bias_max_m = 10.0;
  double noise_sigma_m = 0.4;  // white noise per horizontal axis (standalone fix)
  double height_noise_sigma_m = 0.8;
  double velocity_noise_mps = 0.05;  // per axis
  // Loss of fix: outages start as a Poisson process, each lasting an exponential time.
  double outage_rate_per_min = 0.0;
  double outage_mean_s = 3.0;
  RtkMode rtk = RtkMode::kOff;
  double rtk_fixed_sigma_m = 0.01;  // per axis
  double rtk_float_sigma_m = 0.15;
  double rtk_float_bias_m = 0.3;  // float solutions keep part of the offset
  double rtk_fix_delay_s = 5.0;   // RTK float after start or an outage, then fixed
  int satellites = 14;
  double hdop = 0.9;
  /// UTC of simulation time 0 (Unix ns) for utc_ns / itow_ms. Default 2022-08-20 10:00 UTC.
  std::int64_t utc_at_zero_ns = 1'660'989'600LL * 1'000'000'000LL;
  std::uint64_t seed = 2;

  [[nodiscard]] std::optional<std::string> validate() const;
};

class GnssSim {
 public:
  /// `origin` is the navigation frame's geodetic origin (World::origin).
  GnssSim(const GnssSimConfig& config, const core::GeoPoint& origin);

  /// Produces the fix of the epoch due at or before `now_ns` (epochs fall on whole multiples of
  /// 1/rate_hz of simulation time), true when one was produced; read it with fix(). Call at least
  /// once per epoch; skipped epochs are not back-filled.
  bool update(core::TimeNs now_ns, const BoatTruth& truth);
  [[nodiscard]] const msg::GnssFix& fix() const { return fix_; }
  /// Current bias (north, east) in metres; what a fix is shifted by beyond the noise.
  [[nodiscard]] core::NavPoint bias() const { return {bias_n_, bias_e_}; }
  [[nodiscard]] bool in_outage() const { return outage_until_ns_ > last_epoch_ns_; }
  [[nodiscard]] const GnssSimConfig& config() const { return config_; }
  [[nodiscard]] const core::LocalFrame& frame() const { return frame_; }

 private:
  void step_bias(double dt_s);

  GnssSimConfig config_;
  core::LocalFrame frame_;
  Rng rng_;
  core::TimeNs period_ns_ = 0;
  core::TimeNs last_epoch_ns_ = core::kNeverNs;
  core::TimeNs outage_until_ns_ = core::kNeverNs;
  core::TimeNs next_outage_ns_ = core::kNeverNs;
  core::TimeNs rtk_fixed_from_ns_ = 0;
  double wander_n_ = 0.0;
  double wander_e_ = 0.0;
  double bias_n_ = 0.0;
  double bias_e_ = 0.0;
  msg::GnssFix fix_;
};

}  // namespace coxswain::sim::sensors
