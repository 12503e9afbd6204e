// SPDX-License-Identifier: Apache-2.0
#pragma once
// What every host of the mission core (the daemon, the simulator, replay) records of a step:
// the compact visualization and the named parameter values. Pure; shared so that replay and
// the simulator need nothing of the daemon.
#include <vector>

#include "coxswain/config/boat_config.hpp"
#include "coxswain/config/mission_config.hpp"
#include "coxswain/mission/mission_core.hpp"
#include "coxswain/record/layouts.hpp"
#include "coxswain/record/map_geometry.hpp"
#include "coxswain/record/tick_record.hpp"

namespace coxswain::host {

/// The recorder's compact visualization of one step: pose, chosen direction, the blocked
/// sector and the nearest obstacle segments (as discs at their midpoints). Pure.
void fill_tick_viz(const mission::CoreOutput& out, const config::BoatConfig& boat,
                   record::TickViz& viz);

/// The mission's waypoints, slips, field boundary and no-go areas for the recorder's map
/// channels, in WGS-84 and in the navigation frame the core uses (anchored at the origin).
[[nodiscard]] record::MapGeometry map_geometry(const config::MissionConfig& mission);

/// Every named tunable of `params` (mission::tunable_specs() order) as the recorder's /params
/// channel holds them. The names point at the table's own strings (they live forever).
[[nodiscard]] std::vector<record::NamedValue> named_values(
    const mission::TunableParameters& params);

}  // namespace coxswain::host
