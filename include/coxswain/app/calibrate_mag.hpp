// SPDX-License-Identifier: Apache-2.0
#pragma once
// `coxswain calibrate mag RUN.mcap`: fits the magnetometer's hard- and soft-iron terms to the
// IMU samples of a recorded slow turn in place and writes them under the `imu:` section of the
// devices file (keys mag_hard_iron_x_ut, mag_hard_iron_y_ut, mag_soft_iron_xx/xy/yx/yy; other
// lines and comments kept).
#include <iosfwd>
#include <string>

namespace coxswain::app {

/// Returns 0 on success, 1 when the recording cannot be read or fitted, 2 when the devices file
/// cannot be updated. `devices_file` empty: print the keys only.
int calibrate_mag(const std::string& recording, const std::string& devices_file, std::ostream& out,
                  std::ostream& err);

/// The devices file's text with the calibration keys set in its `imu:` section (replacing any
/// earlier ones); empty when the text has no top-level `imu:` section.
[[nodiscard]] std::string with_mag_calibration(const std::string& devices_yaml,
                                               const std::string& keys_block);

}  // namespace coxswain::app
