// SPDX-License-Identifier: Apache-2.0
#include "sim/runner/recording.hpp"

#include <nlohmann/json.hpp>

#include <chrono>
#include <thread>

#include "coxswain/host/step_record.hpp"
#include "coxswain/msg/camera_detections.hpp"

namespace coxswain::sim::runner {
namespace {

using nlohmann::json;

// How long a tick may wait for the recorder's threads before recording on regardless (the
// recorder then counts what it dropped; replay reports the missing inputs).
constexpr auto kMaxWait = std::chrono::seconds(5);
// Ticks queued for the writer at most (the queue holds RecorderOptions::tick_queue_slots).
constexpr std::uint64_t kMaxTickBacklog = 128;

json point(const core::NavPoint& p) { return json::array({p.north_m, p.east_m}); }

}  // namespace

std::string course_json(const world::World& world) {
  json walls = json::array();
  auto add_wall = [&](const world::Wall& w) {
    json pts = json::array();
    for (const auto& p : w.points) pts.push_back(point(p));
    walls.push_back(pts);
  };
  for (const auto& w : world.walls) add_wall(w);
  for (const auto& d : world.docks) {
    for (const auto& w : d.walls) add_wall(w);
  }
  json buoys = json::array();
  for (const auto& b : world.buoys) {
    buoys.push_back({{"n", b.center.north_m},
                     {"e", b.center.east_m},
                     {"r", b.radius_m},
                     {"colour", std::string(msg::colour_name(b.colour))}});
  }
  json waypoints = json::array();
  for (const auto& w : world.waypoints) {
    waypoints.push_back(
        {{"n", w.position.north_m}, {"e", w.position.east_m}, {"r", w.radius_m}, {"name", w.name}});
  }
  json gates = json::array();
  for (const auto& g : world.gates) {
    gates.push_back({{"name", g.name}, {"left", point(g.left)}, {"right", point(g.right)}});
  }
  return json{{"name", world.name},     {"start", point(world.start.position)},
              {"walls", walls},         {"buoys", buoys},
              {"waypoints", waypoints}, {"gates", gates}}
      .dump();
}

RunRecorder::RunRecorder(std::filesystem::path path, const config::Configuration& config,
                         const core::LatestStore& store, const core::Clock& clock,
                         const std::string& course, const std::string& build_version)
    : boat_(config.boat), viz_(std::make_unique<record::TickViz>()) {
  record::RecorderOptions options;
  options.path = std::move(path);
  options.config_yaml = config::to_yaml(config);
  options.build_version = build_version;
  options.map = host::map_geometry(config.mission);
  options.sync = false;            // a simulation: no power loss to survive, and fdatasync is slow
  options.sampler_thread = false;  // sample() after every lockstep step instead
  if (!course.empty()) options.extra_metadata.push_back({"course", {{"json", course}}});
  recorder_ = std::make_unique<record::Recorder>(std::move(options), &store, clock);
}

RunRecorder::~RunRecorder() { (void)stop(); }

bool RunRecorder::start() {
  started_ = recorder_->start();
  if (started_) sample();  // what the sensors published before the first step
  return started_;
}

std::string RunRecorder::error() const { return recorder_->stats().error; }

void RunRecorder::wait_for_sampler(const core::Snapshot& snapshot) {
  const auto deadline = std::chrono::steady_clock::now() + kMaxWait;
  while (std::chrono::steady_clock::now() < deadline) {
    const record::RecorderStats s = recorder_->stats();
    if (!s.running || s.failed) return;
    const auto& lidar = s[record::RecordChannel::kLidar];
    const auto& tick = s[record::RecordChannel::kTick];
    const bool scan_taken = lidar.written + lidar.dropped >= snapshot.lidar.sequence;
    const bool room = tick_index_ < tick.written + tick.dropped + kMaxTickBacklog;
    if (scan_taken && room) return;
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
}

void RunRecorder::sample() {
  if (!started_) return;
  const auto deadline = std::chrono::steady_clock::now() + kMaxWait;
  while (recorder_->queue_room() == 0 && std::chrono::steady_clock::now() < deadline) {
    const record::RecorderStats s = recorder_->stats();
    if (!s.running || s.failed) break;
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  recorder_->sample();
}

void RunRecorder::record_tick(const core::Snapshot& snapshot, core::TimeNs now_ns,
                              const mission::CoreOutput& out) {
  if (!started_) return;
  wait_for_sampler(snapshot);
  host::fill_tick_viz(out, boat_, *viz_);
  (void)recorder_->record_tick(
      {tick_index_, now_ns, &snapshot, out.command, out.status.state_path.view(), viz_.get()});
  ++tick_index_;
}

void RunRecorder::record_parameters(const mission::TunableParameters& params, core::TimeNs now_ns) {
  if (!started_) return;
  (void)recorder_->record_parameters(tick_index_, now_ns, host::named_values(params));
}

record::RecorderStats RunRecorder::stop(const std::string& judge_json) {
  if (started_) {
    record::MetadataRecords closing;
    if (!judge_json.empty()) closing.push_back({"judge", {{"json", judge_json}}});
    recorder_->stop(std::move(closing));
    started_ = false;
  }
  return recorder_->stats();
}

}  // namespace coxswain::sim::runner
