// SPDX-License-Identifier: Apache-2.0
// RecordedScans: the source team's ROS LaserScans back in the lidar's own angles.
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <utility>

#include "coxswain/core/angles.hpp"
#include "sim/devices/rplidar/emulator.hpp"

namespace coxswain::sim::devices::rplidar {

std::optional<RecordedScans> RecordedScans::load(const std::filesystem::path& path,
                                                 std::string* error) {
  const auto fail = [&](std::string why) -> std::optional<RecordedScans> {
    if (error != nullptr) *error = path.string() + ": " + std::move(why);
    return std::nullopt;
  };
  std::ifstream in(path);
  if (!in) return fail("cannot open");
  RecordedScans out;
  std::string line;
  std::size_t line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.empty()) continue;
    const nlohmann::json j = nlohmann::json::parse(line, nullptr, false);
    if (j.is_discarded() || !j.is_object())
      return fail("line " + std::to_string(line_no) + " is not JSON");
    if (j.value("topic", "") != "scan") continue;
    const auto& ranges = j.find("ranges");
    if (ranges == j.end() || !ranges->is_array() || ranges->empty() || !j.contains("angle_min") ||
        !j.contains("angle_increment")) {
      return fail("scan on line " + std::to_string(line_no) + " lacks ranges/angles");
    }
    if (out.beams_ == 0) out.beams_ = std::min(ranges->size(), Emulator::kMaxBeams);
    const double angle_min = j["angle_min"].get<double>();
    const double increment = j["angle_increment"].get<double>();
    std::vector<float> scan(out.beams_, 0.0F);
    for (std::size_t i = 0; i < ranges->size(); ++i) {
      const auto& r = (*ranges)[i];
      if (!r.is_number()) continue;  // null = no return
      const double range_m = r.get<double>();
      if (!std::isfinite(range_m) || range_m <= 0.0) continue;
      // rplidar_ros publishes theta_ros = pi - theta_raw (counter-clockwise ROS angles).
      const double ros_deg =
          (angle_min + static_cast<double>(i) * increment) * 180.0 / std::numbers::pi;
      const double raw_deg = core::wrap_deg_360(180.0 - ros_deg);
      const auto beam =
          static_cast<std::size_t>(std::llround(raw_deg / 360.0 * static_cast<double>(out.beams_)) %
                                   static_cast<long long>(out.beams_));
      scan[beam] = static_cast<float>(range_m);
    }
    out.scans_.push_back(std::move(scan));
  }
  if (out.scans_.empty()) return fail("no scan lines");
  return out;
}

void RecordedScans::fill(std::uint64_t revolution, std::span<float> ranges_m) const {
  if (scans_.empty() || ranges_m.empty()) return;
  const std::vector<float>& s = scans_[revolution % scans_.size()];
  // Nearest beam when the caller asked for another beam count.
  for (std::size_t i = 0; i < ranges_m.size(); ++i) {
    const std::size_t k = (i * s.size() + ranges_m.size() / 2) / ranges_m.size() % s.size();
    ranges_m[i] = s[k];
  }
}

Emulator::RangeSource RecordedScans::source() const {
  return [scans = *this](std::uint64_t revolution, std::span<float> ranges_m) {
    scans.fill(revolution, ranges_m);
  };
}

}  // namespace coxswain::sim::devices::rplidar
