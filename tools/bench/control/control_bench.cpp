// SPDX-License-Identifier: Apache-2.0
// One full control step per iteration: waypoint/line following -> heading PID + speed schedule ->
// actuator mixer, as the tick thread runs it.
#include <benchmark/benchmark.h>

#include <array>
#include <cmath>

#include "coxswain/control/actuator_mixer.hpp"
#include "coxswain/control/heading_pid.hpp"
#include "coxswain/control/speed_schedule.hpp"
#include "coxswain/core/angles.hpp"
#include "coxswain/guidance/waypoint_follower.hpp"

namespace coxswain {
namespace {

void BM_ControlStep(benchmark::State& state) {
  guidance::WaypointFollower follower;
  const std::array<core::NavPoint, 4> route{{{40, 0}, {40, 40}, {0, 40}, {0, 0}}};
  if (!follower.set_route(route)) state.SkipWithError("route rejected");
  control::HeadingPid pid;
  control::SpeedSchedule speed;
  const control::ActuatorMixer mixer;
  core::NavPoint pos{0.0, 1.0};
  double heading = 0.0;
  core::TimeNs t = 0;
  for (auto _ : state) {
    t += core::ms_to_ns(20);
    pos.north_m = std::fmod(pos.north_m + 0.02, 40.0);  // keeps the route alive
    heading = core::wrap_deg(heading + 0.1);
    const guidance::WaypointGuidance g = follower.update(pos, t);
    const double turn = pid.update({g.desired_heading_deg, heading, t, 1.0});
    const double thrust = speed.update(g.distance_to_go_m, t);
    const msg::ActuatorCommand cmd = mixer.mix({turn, thrust}, t);
    benchmark::DoNotOptimize(cmd);
  }
}
BENCHMARK(BM_ControlStep);

}  // namespace
}  // namespace coxswain
