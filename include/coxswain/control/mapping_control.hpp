// SPDX-License-Identifier: Apache-2.0
#pragma once
// The documents' "mapping control" (000 section 4.3.2): map an angle range linearly onto the
// servo range, then scale by a sensitivity gain alpha:
//   x_map = (x - in_min) / (in_max - in_min) * (out_max - out_min) + out_min;  x_ctl = alpha x_map.
// Here the output range is the unitless turn command (default [-1, 1], centred on 0) so that
// alpha scales around straight ahead; the ActuatorMixer then makes pulses.
#include <optional>
#include <string>

namespace coxswain::control {

struct MappingControlParams {
  double in_min_deg = -90.0;  // psi_e mapped to out_min
  double in_max_deg = 90.0;   // psi_e mapped to out_max
  double out_min = -1.0;
  double out_max = 1.0;
  double alpha = 1.0;         // sensitivity gain (> 0)
  double output_limit = 1.0;  // final clamp of |x_ctl|

  [[nodiscard]] std::optional<std::string> validate() const;
};

/// Stateless map; input outside [in_min, in_max] is clamped first. Thread-safe (const).
class MappingControl {
 public:
  explicit MappingControl(MappingControlParams p = {}) : p_(p) {}
  /// psi_e in degrees (+ = turn to starboard) -> turn command.
  [[nodiscard]] double command(double error_deg) const;

 private:
  MappingControlParams p_;
};

}  // namespace coxswain::control
