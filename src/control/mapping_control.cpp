// SPDX-License-Identifier: Apache-2.0
#include "coxswain/control/mapping_control.hpp"

#include <algorithm>
#include <cmath>

namespace coxswain::control {

std::optional<std::string> MappingControlParams::validate() const {
  if (!(in_max_deg > in_min_deg)) return "mapping: in_max_deg must exceed in_min_deg";
  if (!std::isfinite(out_min) || !std::isfinite(out_max)) return "mapping: output range not finite";
  if (!(alpha > 0.0)) return "mapping: alpha must be > 0";
  if (!(output_limit > 0.0)) return "mapping: output_limit must be > 0";
  return std::nullopt;
}

double MappingControl::command(double error_deg) const {
  if (!std::isfinite(error_deg)) return 0.0;
  const double x = std::clamp(error_deg, p_.in_min_deg, p_.in_max_deg);
  const double x_map =
      (x - p_.in_min_deg) / (p_.in_max_deg - p_.in_min_deg) * (p_.out_max - p_.out_min) +
      p_.out_min;
  return std::clamp(x_map * p_.alpha, -p_.output_limit, p_.output_limit);
}

}  // namespace coxswain::control
