// SPDX-License-Identifier: Apache-2.0
#pragma once
// The daemon's local control interface and live view, on two threads of their own (the control
// socket's, so no network flood delays the operator, and the network one), which write
// LatestStore::operator_input under one mutex:
//  - a Unix stream socket taking line commands (see control_protocol.hpp), one answer line each;
//  - an HTTP server (Boost.Beast) with the shore status page at GET /, GET /api/status and the
//    token-protected POST /api/start|hold|resume|target;
//  - on the same port, the Foxglove WebSocket protocol (subprotocol foxglove.websocket.v1):
//    serverInfo, advertise of /tf, /viz/scene, /viz/scan, /viz/fix, /log, /viz/map,
//    /map/geojson, /camera/image and /camera/annotations (the recorder's JSON schemas),
//    subscribe/unsubscribe, messageData at viz_rate_hz, and parameters.
// The tick thread never blocks on it: publish_tick() and publish_parameters() write lock-free
// latest-value slots; take_parameters() reads one. Everything else runs on the server thread.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <vector>

#include "coxswain/core/clock.hpp"
#include "coxswain/core/latest_store.hpp"
#include "coxswain/live/control_protocol.hpp"
#include "coxswain/mission/mission_core.hpp"
#include "coxswain/msg/camera_detections.hpp"
#include "coxswain/msg/operator_input.hpp"
#include "coxswain/record/map_geometry.hpp"
#include "coxswain/record/tick_record.hpp"

namespace coxswain::live {

struct LiveOptions {
  std::filesystem::path socket_path;  // empty: no control socket
  bool http_enabled = true;
  std::string http_address = "127.0.0.1";
  std::uint16_t http_port = 8765;  // 0: any free port (see LiveServer::http_port())
  double viz_rate_hz = 10.0;       // messageData per channel at most this often
  /// Every state-changing request (buttons, setParameters) needs it, and so does viewing from
  /// another machine; compared in constant time. Empty: control is disabled (viewing stays open
  /// to this computer).
  std::string token;
  /// Host names besides IP literals and "localhost" that name this server (DNS-rebinding guard),
  /// e.g. "boat.local" when the phone opens http://boat.local:8765.
  std::vector<std::string> allowed_hosts;
  /// Browser origins besides the server's own that may use it ("scheme://host[:port]").
  std::vector<std::string> allowed_origins = {"https://app.foxglove.dev"};
  std::size_t max_http_connections = 64;     // HTTP + WebSocket; more are closed at once
  std::size_t max_control_connections = 16;  // control socket; the oldest gives way to a new one
  double header_timeout_s = 10.0;            // a request's header and body, a WebSocket handshake
  double idle_timeout_s = 60.0;         // a WebSocket with no subscription and no request (pings
                                        // do not count); an idle control socket connection
  double write_stall_timeout_s = 10.0;  // a client not taking what it is sent is dropped
  std::size_t max_client_queue_bytes = std::size_t{4} << 20U;  // per WebSocket client
  std::size_t max_ws_message_bytes = std::size_t{64} << 10U;
  /// File descriptors kept free of network clients for devices, recording and the control
  /// socket: HTTP connections are limited to (RLIMIT_NOFILE - reserve) / 2 if that is lower.
  std::size_t fd_reserve = 256;
  std::string name = "coxswain";  // serverInfo name
  /// The mission's geometry for /viz/map and /map/geojson (sent with the track every
  /// map_period_ns, and at once to a new subscriber).
  record::MapGeometry map;
  core::TimeNs map_period_ns = 5 * core::kNsPerSec;
  /// Published as the first OperatorInput when not kUnknown (the daemon's --target).
  msg::Colour initial_target_colour = msg::Colour::kUnknown;
  msg::Shape initial_target_shape = msg::Shape::kUnknown;
  /// Named in the `params` answer, so `coxswain ctl save-params` can write the mission file back
  /// with the live values (absolute; empty: not known).
  std::string mission_file;
  std::string vision_file;
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
  /// Camera image thread: the newest JPEG frame and its detections for /camera/image and
  /// /camera/annotations (`scale` as Recorder::record_image). Copies under a short lock; the
  /// server thread sends it at most viz_rate_hz to subscribers.
  void publish_image(core::TimeNs stamp_ns, std::span<const std::uint8_t> jpeg,
                     const msg::CameraDetections& detections, double scale);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace coxswain::live
