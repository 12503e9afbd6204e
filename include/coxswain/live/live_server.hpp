// SPDX-License-Identifier: Apache-2.0
#pragma once
// The daemon's local control interface and live view, all on one thread of its
// own (the "control thread", the single writer of LatestStore::operator_input):
//  - a Unix stream socket taking line commands (see control_protocol.hpp), one answer line each;
//  - an HTTP server (Boost.Beast) with the shore status page at GET /, GET /api/status and the
//    token-protected POST /api/start|hold|resume|target;
//  - on the same port, the Foxglove WebSocket protocol (subprotocol foxglove.websocket.v1):
//    serverInfo, advertise of /tf, /viz/scene, /viz/scan, /viz/fix, /log (the recorder's JSON
//    schemas), subscribe/unsubscribe, messageData at viz_rate_hz, and parameters.
// The tick thread never blocks on it: publish_tick() and publish_parameters() write lock-free
// latest-value slots; take_parameters() reads one. Everything else runs on the server thread.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

#include "coxswain/core/clock.hpp"
#include "coxswain/core/latest_store.hpp"
#include "coxswain/live/control_protocol.hpp"
#include "coxswain/mission/mission_core.hpp"
#include "coxswain/msg/operator_input.hpp"
#include "coxswain/record/tick_record.hpp"

namespace coxswain::live {

struct LiveOptions {
  std::filesystem::path socket_path;  // empty: no control socket
  bool http_enabled = true;
  std::string http_address = "127.0.0.1";
  std::uint16_t http_port = 8765;  // 0: any free port (see LiveServer::http_port())
  double viz_rate_hz = 10.0;       // messageData per channel at most this often
  std::string token;               // the status page's buttons need it; empty: buttons refused
  std::string name = "coxswain";   // serverInfo name
  /// Published as the first OperatorInput when not kUnknown (the daemon's --target).
  msg::Colour initial_target_colour = msg::Colour::kUnknown;
  msg::Shape initial_target_shape = msg::Shape::kUnknown;
};

/// What the tick hands over each tick. Trivially copyable.
struct LiveTick {
  TickSummary summary;
  record::TickViz viz;
};

/// Thread-safety: start/stop from one owner thread; publish_tick, publish_parameters and
/// take_parameters from the tick thread only; http_port from any thread after start.
class LiveServer {
 public:
  LiveServer(LiveOptions options, core::LatestStore& store, const core::Clock& clock);
  ~LiveServer();
  LiveServer(const LiveServer&) = delete;
  LiveServer& operator=(const LiveServer&) = delete;

  /// Binds the socket and the port, then starts the thread. False with `error` when a bind
  /// failed (nothing runs then).
  bool start(std::string& error);
  /// Closes every connection and joins the thread. Idempotent.
  void stop();
  /// The bound TCP port (useful with http_port 0); 0 when HTTP is off or not started.
  [[nodiscard]] std::uint16_t http_port() const;

  /// Tick thread: this tick's status and visualization. Wait-free; never allocates.
  void publish_tick(const LiveTick& tick, core::TimeNs now_ns);
  /// Tick thread: the parameters in force (after start and after each apply).
  void publish_parameters(const mission::TunableParameters& in_force, core::TimeNs now_ns);
  /// Tick thread: a validated parameter set requested since the last call, if any. Lock-free.
  [[nodiscard]] bool take_parameters(mission::TunableParameters& out);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace coxswain::live
