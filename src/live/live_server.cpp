// SPDX-License-Identifier: Apache-2.0
#include "coxswain/live/live_server.hpp"

#include <spdlog/spdlog.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/un.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <chrono>
#include <cmath>
#include <cstring>
#include <deque>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "coxswain/config/vision_config.hpp"
#include "coxswain/live/request_guard.hpp"
#include "coxswain/mission/tunable_parameters.hpp"
#include "coxswain/record/foxglove.hpp"
#include "coxswain/record/track_line.hpp"
#include "status_page.hpp"

namespace coxswain::live {
namespace {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;
using local_stream = asio::local::stream_protocol;
using nlohmann::json;
namespace fox = record::foxglove;

constexpr std::string_view kSubprotocol = "foxglove.websocket.v1";
constexpr std::size_t kMaxLineBytes = 4096;
constexpr std::size_t kMaxBodyBytes = 8192;
constexpr std::size_t kMaxQueuedFrames = 64;  // per client; a slow client loses viz frames

struct ChannelInfo {
  std::uint32_t id;
  std::string_view topic;
  fox::Schema schema;
};
enum ChannelId : std::uint32_t {
  kTf = 1,
  kScene = 2,
  kScan = 3,
  kFix = 4,
  kLog = 5,
  kMap = 6,
  kGeoJson = 7,
  kImage = 8,
  kAnnotations = 9,
};
// The same topics as the recording's, so one Foxglove layout serves both.
const std::array<ChannelInfo, 9> kChannels = {
    {{kTf, "/tf", fox::Schema::kFrameTransform},
     {kScene, "/viz/scene", fox::Schema::kSceneUpdate},
     {kScan, "/viz/scan", fox::Schema::kLaserScan},
     {kFix, "/viz/fix", fox::Schema::kLocationFix},
     {kLog, "/log", fox::Schema::kLog},
     {kMap, "/viz/map", fox::Schema::kSceneUpdate},
     {kGeoJson, "/map/geojson", fox::Schema::kGeoJson},
     {kImage, "/camera/image", fox::Schema::kCompressedImage},
     {kAnnotations, "/camera/annotations", fox::Schema::kImageAnnotations}}};

std::string message_data(std::uint32_t subscription_id, core::TimeNs stamp_ns,
                         std::string_view payload) {
  std::string frame;
  frame.resize(1 + 4 + 8 + payload.size());
  frame[0] = 0x01;  // messageData
  const std::uint64_t ts = stamp_ns > 0 ? static_cast<std::uint64_t>(stamp_ns) : 0U;
  for (std::size_t i = 0; i < 4; ++i) {
    frame[1 + i] = static_cast<char>((subscription_id >> (8 * i)) & 0xFFU);
  }
  for (std::size_t i = 0; i < 8; ++i) frame[5 + i] = static_cast<char>((ts >> (8 * i)) & 0xFFU);
  std::memcpy(frame.data() + 13, payload.data(), payload.size());
  return frame;
}

std::chrono::steady_clock::duration seconds(double s) {
  return std::chrono::duration_cast<std::chrono::steady_clock::duration>(
      std::chrono::duration<double>(s));
}

bool is_loopback(const asio::ip::address& a) {
  if (a.is_v6() && a.to_v6().is_v4_mapped()) {
    return asio::ip::make_address_v4(asio::ip::v4_mapped, a.to_v6()).is_loopback();
  }
  return a.is_loopback();
}

// Accept errors that mean "out of descriptors or memory": wait before the next try rather than
// spin on a backlog that cannot be taken.
bool resource_exhausted(const boost::system::error_code& ec) {
  return ec == boost::system::errc::too_many_files_open ||
         ec == boost::system::errc::too_many_files_open_in_system ||
         ec == boost::system::errc::no_buffer_space || ec == boost::system::errc::not_enough_memory;
}

}  // namespace

struct LiveServer::Impl {
  class ControlSession;
  class HttpSession;
  class WsSession;

  Impl(LiveOptions o, core::LatestStore& s, const core::Clock& c)
      : options(std::move(o)),
        store(s),
        clock(c),
        unix_acceptor(control_ioc),
        tcp_acceptor(ioc),
        viz_timer(ioc),
        sweep_timer(ioc),
        tcp_retry_timer(ioc),
        unix_retry_timer(control_ioc),
        control_sweep_timer(control_ioc),
        devices(std::make_unique<core::Snapshot>()),
        scan(std::make_unique<core::Sample<msg::LidarScan>>()) {}

  // ---- shared state, server thread unless noted ----------------------------------------------
  LiveOptions options;
  core::LatestStore& store;
  const core::Clock& clock;
  asio::io_context ioc;
  // The control socket has a thread of its own, so no flood on the network side delays the
  // operator's `ctl hold`.
  asio::io_context control_ioc;
  std::thread control_thread;
  local_stream::acceptor unix_acceptor;
  tcp::acceptor tcp_acceptor;
  asio::steady_timer viz_timer;
  asio::steady_timer sweep_timer;
  asio::steady_timer tcp_retry_timer;
  asio::steady_timer unix_retry_timer;
  asio::steady_timer control_sweep_timer;
  // Guards operator_state, devices and the operator_input slot (whose single writer is whoever
  // holds it): the control thread and the network thread both run commands.
  std::mutex state_mutex;
  std::thread thread;
  std::atomic<std::uint16_t> port{0};
  bool started = false;
  bool socket_bound = false;

  OperatorState operator_state;
  std::unique_ptr<core::Snapshot> devices;  // health only, for status answers
  std::unique_ptr<core::Sample<msg::LidarScan>> scan;
  std::vector<std::weak_ptr<WsSession>> clients;
  std::uint64_t sent_tick_seq = 0;
  std::uint64_t sent_scan_seq = 0;
  std::uint64_t sent_fix_seq = 0;
  // The map: the track since start (kept with or without viewers, so a late one sees it all),
  // sent every map_period_ns and at once to a new subscriber.
  record::TrackLine track;
  core::TimeNs last_map_ns = 0;
  std::size_t map_subscriptions = 0;
  // UTC minus the injected clock, taken at start: the viewers' stamps are wall-clock times (as
  // in the recording), so Foxglove's timeline shows when the boat sails, not 1970.
  core::TimeNs utc_offset_ns = 0;
  // The newest camera image (camera image thread -> server thread).
  struct Image {
    std::uint64_t sequence = 0;
    core::TimeNs stamp_ns = 0;
    std::vector<std::uint8_t> jpeg;
    msg::CameraDetections detections{};
    double scale = 1.0;
  };
  std::mutex image_mutex;
  Image image;       // guarded by image_mutex
  Image image_copy;  // server thread
  std::uint64_t sent_image_seq = 0;
  std::optional<mission::TunableParameters> pending;  // latest requested set

  // Bounded resources (server thread).
  std::size_t max_tcp = 0;  // options.max_http_connections, lowered by the descriptor reserve
  std::size_t tcp_connections = 0;
  std::vector<std::weak_ptr<ControlSession>> control_sessions;  // oldest first; control thread
  bool trim_memory = false;  // a client with queued data went away: give the memory back
  // One warning per kind and period however many requests are refused.
  WarningLimiter refused_limiter{std::chrono::seconds(10)};
  WarningLimiter overflow_limiter{std::chrono::seconds(10)};
  WarningLimiter accept_limiter{std::chrono::seconds(10)};
  WarningLimiter control_accept_limiter{std::chrono::seconds(10)};  // control thread
  WarningLimiter dropped_limiter{std::chrono::seconds(10)};

  static void warn_limited(WarningLimiter& limiter, const std::string& text) {
    std::uint64_t suppressed = 0;
    if (!limiter.allow(WarningLimiter::Clock::now(), suppressed)) return;
    if (suppressed == 0) {
      spdlog::warn("{}", text);
    } else {
      spdlog::warn("{} ({} more like it not logged)", text, suppressed);
    }
  }

  // Holds one of the max_tcp places for as long as a connection (HTTP, then WebSocket) lives.
  class TcpSlot {
   public:
    explicit TcpSlot(Impl& impl) : impl_(&impl) { ++impl_->tcp_connections; }
    ~TcpSlot() {
      if (impl_ != nullptr) --impl_->tcp_connections;
    }
    TcpSlot(TcpSlot&& o) noexcept : impl_(std::exchange(o.impl_, nullptr)) {}
    TcpSlot& operator=(TcpSlot&&) = delete;
    TcpSlot(const TcpSlot&) = delete;
    TcpSlot& operator=(const TcpSlot&) = delete;

   private:
    Impl* impl_;
  };

  // Cross-thread slots (writer named per slot).
  core::LatestSlot<LiveTick> tick_slot;                         // tick thread
  core::LatestSlot<mission::TunableParameters> in_force_slot;   // tick thread
  core::LatestSlot<mission::TunableParameters> requested_slot;  // server thread
  std::uint64_t consumed_request = 0;                           // tick thread
  // The newest request the tick has applied (its requested_slot sequence), published with the
  // parameters then in force: a set is answered once it is applied, with what was applied.
  std::atomic<std::uint64_t> applied_request{0};  // tick thread writes

  void publish_operator(const msg::OperatorInput& in) {
    store.operator_input.publish(in, in.stamp_ns);
  }

  // ---- commands ------------------------------------------------------------------------------
  std::string status_answer() {
    const std::lock_guard lock(state_mutex);
    const core::TimeNs now = clock.now_ns();
    for (std::size_t i = 0; i < msg::kDeviceCount; ++i) store.health[i].read(devices->health[i]);
    core::Sample<TickSummary> summary;
    const core::Sample<LiveTick> t = tick_slot.read();
    summary.value = t.value.summary;
    summary.stamp_ns = t.stamp_ns;
    summary.sequence = t.sequence;
    json answer =
        json::parse(status_json(summary, operator_state.current(), *devices, now), nullptr, false);
    if (!answer.is_object()) return status_json(summary, operator_state.current(), *devices, now);
    answer["controls"] = controls_json();
    return answer.dump(-1, ' ', false, json::error_handler_t::replace);
  }

  // The parameters in force: every named one, the vision file they make (write_vision, so it
  // loads back unchanged) and the files the daemon started from.
  std::string params_answer() {
    const core::Sample<mission::TunableParameters> in_force = in_force_slot.read();
    if (!in_force.valid()) {
      return json{{"ok", false}, {"error", "no parameters in force yet"}}.dump();
    }
    json values = json::object();
    for (const mission::TunableSpec& spec : mission::tunable_specs()) {
      const double v = spec.get(in_force.value);
      if (std::isfinite(v)) values[spec.name] = v;
    }
    std::ostringstream vision;
    config::write_vision(in_force.value.vision, vision);
    json answer = {{"ok", true},
                   {"parameters", std::move(values)},
                   {"vision_yaml", vision.str()},
                   {"mission_file", options.mission_file},
                   {"vision_file", options.vision_file}};
    return answer.dump(-1, ' ', false, json::error_handler_t::replace);
  }

  // Whether the buttons and live tuning can work at all, and if not how to make them.
  json controls_json() const {
    if (options.token.empty()) {
      return {{"enabled", false},
              {"why", "no token is configured (live.token in devices.yaml is empty)"},
              {"how",
               "set live.token in devices.yaml to a secret of your choice, restart the daemon, "
               "then enter that token on this page (Foxglove: ws://HOST:PORT/?token=...)"}};
    }
    return {{"enabled", true}, {"how", "enter live.token of devices.yaml on this page"}};
  }

  // Runs a parsed command; returns the JSON answer line (no newline).
  std::string run_command(const ControlCommand& cmd, std::string_view via) {
    if (cmd.kind == CommandKind::kStatus) return status_answer();
    if (cmd.kind == CommandKind::kParams) return params_answer();
    {
      const std::lock_guard lock(state_mutex);
      publish_operator(operator_state.apply(cmd, clock.now_ns()));
    }
    std::string what;
    switch (cmd.kind) {
      case CommandKind::kStart:
        what = "start";
        break;
      case CommandKind::kHold:
        what = "hold";
        break;
      case CommandKind::kResume:
        what = "resume";
        break;
      case CommandKind::kTarget:
        what = "target " + std::string(msg::colour_name(cmd.colour)) + " " +
               std::string(msg::shape_name(cmd.shape));
        break;
      case CommandKind::kStatus:
      case CommandKind::kParams:
        break;
    }
    spdlog::info("control: {} (from {})", what, via);
    // The WebSocket clients belong to the network thread.
    asio::post(ioc, [this, text = "operator: " + what + " (from " + std::string(via) + ")"] {
      emit_log(fox::LogLevel::kInfo, text);
    });
    json j = {{"ok", true}, {"command", what}};
    return j.dump();
  }

  std::string handle_line(std::string_view line) {
    std::string error;
    const auto cmd = parse_command(line, error);
    if (!cmd) {
      return json{{"ok", false}, {"error", error}}.dump(-1, ' ', false,
                                                        json::error_handler_t::replace);
    }
    return run_command(*cmd, "control socket");
  }

  // ---- HTTP ----------------------------------------------------------------------------------
  // Why a request may not be served at all (wrong Host or Origin, or viewing from another
  // machine without the token); nullopt when it may.
  std::optional<std::pair<http::status, std::string>> refusal(
      const http::request<http::string_body>& req, bool loopback_peer) {
    const auto host_it = req.find(http::field::host);
    const std::string_view host =
        host_it == req.end() ? std::string_view()
                             : std::string_view(host_it->value().data(), host_it->value().size());
    const auto origin_it = req.find(http::field::origin);
    const std::optional<std::string_view> origin =
        origin_it == req.end() ? std::nullopt
                               : std::optional<std::string_view>(std::string_view(
                                     origin_it->value().data(), origin_it->value().size()));
    if (!host_allowed(host, options.allowed_hosts)) {
      return std::make_pair(http::status::forbidden,
                            "Host '" + std::string(host.substr(0, 100)) +
                                "' does not name this server (live.allowed_hosts)");
    }
    if (!origin_allowed(origin, host, options.allowed_origins)) {
      return std::make_pair(http::status::forbidden,
                            "Origin '" + std::string(origin->substr(0, 100)) +
                                "' may not use this server (live.allowed_origins)");
    }
    const std::string_view target(req.target().data(), req.target().size());
    const std::string_view path = path_of(target);
    if (!loopback_peer && path != "/" && path != "/index.html" &&
        !token_matches(options.token, presented_token(req))) {
      return std::make_pair(http::status::unauthorized,
                            options.token.empty()
                                ? std::string("no token is configured: only this computer may "
                                              "view the live data")
                                : std::string("from another machine the live view needs the token "
                                              "(X-Coxswain-Token or ?token=)"));
    }
    return std::nullopt;
  }

  // The token a request carries: the X-Coxswain-Token header, else `?token=` (a Foxglove
  // client can only put it in the URL).
  static std::string_view presented_token(const http::request<http::string_body>& req) {
    const auto it = req.find("X-Coxswain-Token");
    if (it != req.end()) return {it->value().data(), it->value().size()};
    const std::string_view target(req.target().data(), req.target().size());
    return query_token(target).value_or(std::string_view());
  }

  void refused(std::string_view what, std::string_view why, const std::string& peer) {
    warn_limited(refused_limiter,
                 "live: refused " + std::string(what) + " from " + peer + ": " + std::string(why));
  }

  http::response<http::string_body> error_response(const http::request<http::string_body>& req,
                                                   http::status status, std::string_view text) {
    http::response<http::string_body> res{status, req.version()};
    res.set(http::field::server, "coxswain");
    res.set(http::field::cache_control, "no-store");
    res.set(http::field::content_type, "application/json");
    res.keep_alive(false);
    res.body() =
        json{{"ok", false}, {"error", text}}.dump(-1, ' ', false, json::error_handler_t::replace);
    res.prepare_payload();
    return res;
  }

  http::response<http::string_body> handle_http(const http::request<http::string_body>& req,
                                                const std::string& peer) {
    http::response<http::string_body> res;
    res.version(req.version());
    res.keep_alive(req.keep_alive());
    res.set(http::field::server, "coxswain");
    res.set(http::field::cache_control, "no-store");
    const auto reply = [&](http::status status, std::string_view type, std::string body) {
      res.result(status);
      res.set(http::field::content_type, beast::string_view(type.data(), type.size()));
      res.body() = std::move(body);
      res.prepare_payload();
      return res;
    };
    const auto error = [&](http::status status, std::string_view text) {
      return reply(status, "application/json",
                   json{{"ok", false}, {"error", text}}.dump(-1, ' ', false,
                                                             json::error_handler_t::replace));
    };
    const std::string_view target =
        path_of(std::string_view(req.target().data(), req.target().size()));
    if (target == "/" || target == "/index.html") {
      if (req.method() != http::verb::get) return error(http::status::method_not_allowed, "GET");
      return reply(http::status::ok, "text/html; charset=utf-8", std::string(kStatusPageHtml));
    }
    if (target == "/api/status") {
      if (req.method() != http::verb::get) return error(http::status::method_not_allowed, "GET");
      return reply(http::status::ok, "application/json", status_answer());
    }
    std::optional<CommandKind> kind;
    if (target == "/api/start") kind = CommandKind::kStart;
    if (target == "/api/hold") kind = CommandKind::kHold;
    if (target == "/api/resume") kind = CommandKind::kResume;
    if (target == "/api/target") kind = CommandKind::kTarget;
    if (!kind) return error(http::status::not_found, "no such resource");
    if (req.method() != http::verb::post) return error(http::status::method_not_allowed, "POST");
    const auto token_it = req.find("X-Coxswain-Token");
    const std::string_view presented =
        token_it == req.end()
            ? std::string_view()
            : std::string_view(token_it->value().data(), token_it->value().size());
    if (!token_matches(options.token, presented)) {
      refused("POST " + std::string(target), "no valid token", peer);
      return error(http::status::unauthorized,
                   options.token.empty() ? "no token is configured: the buttons are disabled"
                                         : "bad or missing X-Coxswain-Token");
    }
    ControlCommand cmd{*kind, msg::Colour::kUnknown, msg::Shape::kUnknown};
    if (*kind == CommandKind::kTarget) {
      const json body = json::parse(req.body(), nullptr, false);
      if (!body.is_object() || !body.contains("colour") || !body.contains("shape") ||
          !body["colour"].is_string() || !body["shape"].is_string()) {
        return error(http::status::bad_request, "body must be {\"colour\": ..., \"shape\": ...}");
      }
      const auto colour = parse_colour(body["colour"].get<std::string>());
      const auto shape = parse_shape(body["shape"].get<std::string>());
      if (!colour || !shape) return error(http::status::bad_request, "unknown colour or shape");
      cmd.colour = *colour;
      cmd.shape = *shape;
    }
    return reply(http::status::ok, "application/json", run_command(cmd, "status page"));
  }

  // ---- Foxglove ------------------------------------------------------------------------------
  static std::string server_info() {
    json j = {{"op", "serverInfo"},
              {"name", "coxswain"},
              {"capabilities", json::array({"parameters"})},
              {"supportedEncodings", json::array()},
              {"metadata", json::object()}};
    return j.dump();
  }
  static std::string advertise() {
    json channels = json::array();
    for (const ChannelInfo& c : kChannels) {
      channels.push_back({{"id", c.id},
                          {"topic", std::string(c.topic)},
                          {"encoding", std::string(fox::kMessageEncoding)},
                          {"schemaName", std::string(fox::schema_name(c.schema))},
                          {"schema", fox::schema_json(c.schema)},
                          {"schemaEncoding", std::string(fox::kSchemaEncoding)}});
    }
    return json{{"op", "advertise"}, {"channels", std::move(channels)}}.dump();
  }

  static json status_op(int level, std::string_view message, const json& id) {
    json j = {{"op", "status"}, {"level", level}, {"message", message}};
    if (!id.is_null()) j["id"] = id;
    return j;
  }

  // An enumeration by its name ("strategy": "gap_follow"), anything else as its number.
  static json parameter_json(const mission::TunableSpec& spec,
                             const mission::TunableParameters& params) {
    const double value = spec.get(params);
    if (!spec.choices.empty() && value >= 0.0 && value < static_cast<double>(spec.choices.size())) {
      return spec.choices[static_cast<std::size_t>(value)];
    }
    return value;
  }

  // A requested value: a number, or for an enumeration one of its names. Null when neither.
  static std::optional<double> requested_value(const mission::TunableSpec* spec, const json& v) {
    if (v.is_number()) return v.get<double>();
    if (v.is_string() && spec != nullptr) {
      for (std::size_t i = 0; i < spec->choices.size(); ++i) {
        if (spec->choices[i] == v.get<std::string>()) return static_cast<double>(i);
      }
    }
    return std::nullopt;
  }

  json parameter_values(const std::vector<std::string>& names, const json& id) {
    json params = json::array();
    const core::Sample<mission::TunableParameters> in_force = in_force_slot.read();
    if (in_force.valid()) {
      for (const mission::TunableSpec& spec : mission::tunable_specs()) {
        bool wanted = names.empty();
        for (const std::string& n : names) wanted = wanted || n == spec.name;
        if (!wanted) continue;
        params.push_back({{"name", spec.name}, {"value", parameter_json(spec, in_force.value)}});
      }
    }
    json j = {{"op", "parameterValues"}, {"parameters", std::move(params)}};
    if (!id.is_null()) j["id"] = id;
    return j;
  }

  // Validates and queues a set request; returns the status messages to send (empty: all ok).
  // `request_seq`: the requested_slot sequence of the published set (0: nothing published).
  std::vector<json> set_parameters(const json& list, const json& id,
                                   std::vector<std::string>& names, std::uint64_t& request_seq) {
    request_seq = 0;
    std::vector<json> problems;
    if (!pending) {
      const core::Sample<mission::TunableParameters> in_force = in_force_slot.read();
      if (!in_force.valid()) {
        problems.push_back(status_op(2, "the mission core is not running yet", id));
        return problems;
      }
      pending = in_force.value;
    }
    mission::TunableParameters candidate = *pending;
    bool changed = false;
    for (const json& p : list) {
      if (!p.is_object() || !p.contains("name") || !p["name"].is_string()) continue;
      const std::string name = p["name"].get<std::string>();
      names.push_back(name);
      const mission::TunableSpec* spec = mission::find_tunable(name);
      const std::optional<double> requested =
          p.contains("value") ? requested_value(spec, p["value"]) : std::nullopt;
      if (!requested) {
        std::string need = name + ": a number is required";
        if (spec != nullptr && !spec->choices.empty()) {
          need = name + ": one of";
          for (const std::string& c : spec->choices) need += " " + c;
          need += " (or its number) is required";
        }
        problems.push_back(status_op(2, need, id));
        continue;
      }
      const std::string err = mission::set_tunable(candidate, name, *requested);
      if (!err.empty()) {
        problems.push_back(status_op(2, "rejected: " + err, id));
        spdlog::warn("live: parameter {} rejected: {}", name, err);
        emit_log(fox::LogLevel::kWarning, fmt::format("parameter {} rejected: {}", name, err));
        continue;
      }
      // Logged as the client will see it: an enumeration by its name.
      std::string shown = json(*requested).dump();
      if (spec != nullptr && *requested >= 0.0 &&
          *requested < static_cast<double>(spec->choices.size())) {
        shown = spec->choices[static_cast<std::size_t>(*requested)];
      }
      spdlog::info("live: parameter {} = {} requested", name, shown);
      emit_log(fox::LogLevel::kInfo, fmt::format("parameter {} = {} requested", name, shown));
      changed = true;
    }
    if (changed) {
      pending = candidate;
      requested_slot.publish(candidate, clock.now_ns());
      request_seq = requested_slot.sequence();
    }
    return problems;
  }

  void emit_log(fox::LogLevel level, const std::string& text);
  void on_viz_timer();
  void arm_viz_timer() {
    const double period_s = 1.0 / options.viz_rate_hz;
    viz_timer.expires_after(std::chrono::nanoseconds(core::sec_to_ns(period_s)));
    viz_timer.async_wait([this](const boost::system::error_code& ec) {
      if (!ec) on_viz_timer();
    });
  }
  void accept_unix();
  void accept_tcp();
  void sweep();
  void control_sweep();
};

// One client of the control socket: a line in, a line out, until it closes, idles past
// idle_timeout_s, or gives way to a newer client when max_control_connections are open.
class LiveServer::Impl::ControlSession : public std::enable_shared_from_this<ControlSession> {
 public:
  ControlSession(local_stream::socket socket, Impl& impl)
      : socket_(std::move(socket)),
        buffer_(kMaxLineBytes),
        impl_(impl),
        last_activity_(std::chrono::steady_clock::now()) {}
  void read() {
    asio::async_read_until(socket_, buffer_, '\n',
                           [self = shared_from_this()](const boost::system::error_code& ec,
                                                       std::size_t n) { self->on_line(ec, n); });
  }
  void close() {
    boost::system::error_code ignored;
    socket_.close(ignored);
  }
  [[nodiscard]] bool open() const { return socket_.is_open(); }
  [[nodiscard]] std::chrono::steady_clock::time_point last_activity() const {
    return last_activity_;
  }

 private:
  void on_line(const boost::system::error_code& ec, std::size_t n) {
    if (ec) {  // closed, or a line longer than kMaxLineBytes
      close();
      return;
    }
    last_activity_ = std::chrono::steady_clock::now();
    std::string line(asio::buffers_begin(buffer_.data()),
                     asio::buffers_begin(buffer_.data()) + static_cast<std::ptrdiff_t>(n - 1));
    buffer_.consume(n);
    answer_ = impl_.handle_line(line) + "\n";
    asio::async_write(
        socket_, asio::buffer(answer_),
        [self = shared_from_this()](const boost::system::error_code& wec, std::size_t) {
          self->last_activity_ = std::chrono::steady_clock::now();
          if (wec) {
            self->close();
            return;
          }
          self->read();
        });
  }
  local_stream::socket socket_;
  asio::streambuf buffer_;
  std::string answer_;
  Impl& impl_;
  std::chrono::steady_clock::time_point last_activity_;
};

// One Foxglove WebSocket client.
class LiveServer::Impl::WsSession : public std::enable_shared_from_this<WsSession> {
 public:
  WsSession(tcp::socket socket, Impl& impl, TcpSlot slot, bool may_control, std::string peer)
      : ws_(std::move(socket)),
        impl_(impl),
        slot_(std::move(slot)),
        may_control_(may_control),
        peer_(std::move(peer)),
        last_request_(std::chrono::steady_clock::now()) {}

  // The upgrade request is read while async_accept starts (Beast builds its response there).
  void run(const http::request<http::string_body>& req) {
    websocket::stream_base::timeout timeout{};
    timeout.handshake_timeout = seconds(impl_.options.header_timeout_s);
    timeout.idle_timeout = websocket::stream_base::none();  // see LiveServer::Impl::sweep
    timeout.keep_alive_pings = false;
    ws_.set_option(timeout);
    ws_.set_option(websocket::stream_base::decorator([](websocket::response_type& res) {
      res.set(http::field::sec_websocket_protocol,
              beast::string_view(kSubprotocol.data(), kSubprotocol.size()));
      res.set(http::field::server, "coxswain");
    }));
    ws_.read_message_max(impl_.options.max_ws_message_bytes);
    ws_.async_accept(req, [self = shared_from_this()](const boost::system::error_code& ec) {
      if (ec) {
        self->close();
        return;
      }
      self->impl_.clients.push_back(self);
      self->send(server_info(), false);
      self->send(advertise(), false);
      self->read();
    });
  }

  [[nodiscard]] bool open() const { return open_; }

  // Sends the parameterValues answers whose set the tick has applied (sequence `applied`), and
  // after kAnswerTimeout those it has not (then with what is in force and a warning).
  void answer_applied(std::uint64_t applied) {
    if (answers_.empty() || !open_) return;
    const auto now = std::chrono::steady_clock::now();
    for (auto it = answers_.begin(); it != answers_.end();) {
      const bool done = it->request_seq <= applied;
      if (!done && now < it->deadline) {
        ++it;
        continue;
      }
      if (!done) {
        send(status_op(1, "the parameter set is not applied yet (is the mission core ticking?)",
                       it->id)
                 .dump(-1, ' ', false, json::error_handler_t::replace),
             false);
      }
      send(impl_.parameter_values(it->names, it->id)
               .dump(-1, ' ', false, json::error_handler_t::replace),
           false);
      it = answers_.erase(it);
    }
  }

  // Subscription ids of this client on `channel`.
  void subscriptions_of(std::uint32_t channel, std::vector<std::uint32_t>& out) const {
    out.clear();
    for (const auto& [sub, ch] : subs_) {
      if (ch == channel) out.push_back(sub);
    }
  }
  [[nodiscard]] bool subscribed(std::uint32_t channel) const {
    for (const auto& s : subs_) {
      if (s.second == channel) return true;
    }
    return false;
  }

  // Visualization frames (binary) are dropped for a client that is behind; a reply (text) that
  // does not fit in its queue drops the client, which is not reading what it asks for.
  void send(std::string data, bool binary) {
    if (!open_) return;
    const std::size_t limit = impl_.options.max_client_queue_bytes;
    if (queued_bytes_ + data.size() > limit || (binary && queue_.size() >= kMaxQueuedFrames)) {
      if (binary) return;
      impl_.warn_limited(impl_.overflow_limiter, "live: dropped WebSocket client " + peer_ +
                                                     ": it does not read its "
                                                     "replies (" +
                                                     std::to_string(queued_bytes_) +
                                                     " bytes queued)");
      close();
      return;
    }
    queued_bytes_ += data.size();
    queue_.push_back({std::move(data), binary});
    if (!writing_) write_next();
  }

  // Closes the connection: pending operations end with an error and release the session.
  void close() {
    if (!open_ && !beast::get_lowest_layer(ws_).socket().is_open()) return;
    open_ = false;
    if (queued_bytes_ > 0) impl_.trim_memory = true;
    // The front element may be in an async_write; the rest can go now.
    while (queue_.size() > (writing_ ? 1U : 0U)) {
      queued_bytes_ -= queue_.back().data.size();
      queue_.pop_back();
    }
    boost::system::error_code ignored;
    beast::get_lowest_layer(ws_).socket().shutdown(tcp::socket::shutdown_both, ignored);
    beast::get_lowest_layer(ws_).socket().close(ignored);
  }

  // Called about once a second: drops an idle client (no subscription, no request: pings do not
  // count) and one that stopped taking data.
  void sweep(std::chrono::steady_clock::time_point now) {
    if (!open_) return;
    if (writing_ && now - write_started_ > seconds(impl_.options.write_stall_timeout_s)) {
      impl_.warn_limited(impl_.dropped_limiter,
                         "live: dropped WebSocket client " + peer_ + ": not reading");
      close();
    } else if (subs_.empty() && now - last_request_ > seconds(impl_.options.idle_timeout_s)) {
      impl_.warn_limited(impl_.dropped_limiter, "live: closed idle WebSocket client " + peer_);
      close();
    }
  }

 private:
  struct Out {
    std::string data;
    bool binary;
  };
  void write_next() {
    writing_ = true;
    write_started_ = std::chrono::steady_clock::now();
    ws_.binary(queue_.front().binary);
    ws_.async_write(asio::buffer(queue_.front().data),
                    [self = shared_from_this()](const boost::system::error_code& ec, std::size_t) {
                      self->queued_bytes_ -= self->queue_.front().data.size();
                      self->queue_.pop_front();
                      self->writing_ = false;
                      if (ec) {
                        self->close();
                        return;
                      }
                      if (!self->queue_.empty() && self->open_) self->write_next();
                    });
  }
  void read() {
    ws_.async_read(buffer_,
                   [self = shared_from_this()](const boost::system::error_code& ec, std::size_t) {
                     if (ec) {
                       self->close();
                       return;
                     }
                     self->last_request_ = std::chrono::steady_clock::now();
                     if (self->ws_.got_text())
                       self->on_text(beast::buffers_to_string(self->buffer_.data()));
                     self->buffer_.consume(self->buffer_.size());
                     if (self->open_) self->read();
                   });
  }
  void on_text(const std::string& text) {
    const json msg = json::parse(text, nullptr, false);
    if (!msg.is_object() || !msg.contains("op") || !msg["op"].is_string()) {
      send(status_op(1, "not a JSON object with an op", json()).dump(), false);
      return;
    }
    const std::string op = msg["op"].get<std::string>();
    const json id = msg.contains("id") ? msg["id"] : json();
    if (op == "subscribe" && msg.contains("subscriptions") && msg["subscriptions"].is_array()) {
      for (const json& s : msg["subscriptions"]) {
        if (!s.is_object() || !s.contains("id") || !s.contains("channelId") ||
            !s["id"].is_number_unsigned() || !s["channelId"].is_number_unsigned()) {
          continue;
        }
        const auto ch = s["channelId"].get<std::uint32_t>();
        bool known = false;
        for (const ChannelInfo& c : kChannels) known = known || c.id == ch;
        if (!known) {
          send(status_op(1, "no channel " + std::to_string(ch), json()).dump(), false);
          continue;
        }
        if (subs_.size() >= kMaxSubscriptions) {
          send(status_op(1, "too many subscriptions", json()).dump(), false);
          break;
        }
        subs_.emplace_back(s["id"].get<std::uint32_t>(), ch);
      }
    } else if (op == "unsubscribe" && msg.contains("subscriptionIds") &&
               msg["subscriptionIds"].is_array()) {
      for (const json& s : msg["subscriptionIds"]) {
        if (!s.is_number_unsigned()) continue;
        const auto sub = s.get<std::uint32_t>();
        std::erase_if(subs_, [sub](const auto& e) { return e.first == sub; });
      }
    } else if (op == "getParameters") {
      std::vector<std::string> names;
      if (msg.contains("parameterNames") && msg["parameterNames"].is_array()) {
        for (const json& n : msg["parameterNames"]) {
          if (n.is_string()) names.push_back(n.get<std::string>());
        }
      }
      send(impl_.parameter_values(names, id).dump(-1, ' ', false, json::error_handler_t::replace),
           false);
    } else if (op == "setParameters" && msg.contains("parameters") &&
               msg["parameters"].is_array()) {
      if (!may_control_) {
        const std::string why = impl_.options.token.empty()
                                    ? "no token is configured: live tuning is disabled"
                                    : "setParameters needs the token: connect to "
                                      "ws://HOST:PORT/?token=...";
        impl_.refused("setParameters", why, peer_);
        send(status_op(2, why, id).dump(-1, ' ', false, json::error_handler_t::replace), false);
        return;
      }
      std::vector<std::string> names;
      std::uint64_t request_seq = 0;
      for (const json& problem : impl_.set_parameters(msg["parameters"], id, names, request_seq)) {
        send(problem.dump(-1, ' ', false, json::error_handler_t::replace), false);
      }
      if (!id.is_null()) {
        // Answered with the values in force once the tick has applied the set (the next tick,
        // on_viz_timer looks), so the answer is what applies, not what was asked.
        if (answers_.size() >= kMaxPendingAnswers) answers_.erase(answers_.begin());
        answers_.push_back(
            {id, std::move(names), request_seq, std::chrono::steady_clock::now() + kAnswerTimeout});
        answer_applied(impl_.applied_request.load());
      }
    } else {
      send(status_op(1, "unsupported op '" + op + "'", json())
               .dump(-1, ' ', false, json::error_handler_t::replace),
           false);
    }
  }

  static constexpr std::size_t kMaxSubscriptions = 64;
  static constexpr std::size_t kMaxPendingAnswers = 16;
  static constexpr std::chrono::seconds kAnswerTimeout{2};
  struct PendingAnswer {
    json id;
    std::vector<std::string> names;
    std::uint64_t request_seq = 0;  // 0: nothing was published, answer at once
    std::chrono::steady_clock::time_point deadline;
  };
  std::vector<PendingAnswer> answers_;
  websocket::stream<beast::tcp_stream> ws_;
  beast::flat_buffer buffer_;
  std::deque<Out> queue_;
  std::size_t queued_bytes_ = 0;
  bool writing_ = false;
  bool open_ = true;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> subs_;  // subscription id, channel id
  Impl& impl_;
  TcpSlot slot_;
  bool may_control_;
  std::string peer_;
  std::chrono::steady_clock::time_point last_request_;
  std::chrono::steady_clock::time_point write_started_;
};

// One HTTP connection; hands itself over to a WsSession on an upgrade request. Each request
// (header and body) must arrive within header_timeout_s, and so must the next one on a kept-alive
// connection.
class LiveServer::Impl::HttpSession : public std::enable_shared_from_this<HttpSession> {
 public:
  HttpSession(tcp::socket socket, Impl& impl, TcpSlot slot)
      : stream_(std::move(socket)), impl_(impl), slot_(std::move(slot)) {
    boost::system::error_code ec;
    const tcp::endpoint remote = stream_.socket().remote_endpoint(ec);
    loopback_ = !ec && is_loopback(remote.address());
    peer_ =
        ec ? std::string("?") : remote.address().to_string() + ":" + std::to_string(remote.port());
  }
  void read() {
    parser_.emplace();
    parser_->header_limit(kMaxHeaderBytes);
    parser_->body_limit(kMaxBodyBytes);
    stream_.expires_after(seconds(impl_.options.header_timeout_s));
    http::async_read(stream_, buffer_, *parser_,
                     [self = shared_from_this()](const boost::system::error_code& ec, std::size_t) {
                       self->on_read(ec);
                     });
  }

 private:
  void on_read(const boost::system::error_code& ec) {
    if (ec) return;
    const http::request<http::string_body>& req = parser_->get();
    const bool upgrade = websocket::is_upgrade(req);
    if (const auto why = impl_.refusal(req, loopback_)) {
      impl_.refused(upgrade ? "a WebSocket" : "an HTTP request", why->second, peer_);
      response_ = impl_.error_response(req, why->first, why->second);
      write();
      return;
    }
    if (upgrade) {
      stream_.expires_never();
      const bool may_control = token_matches(impl_.options.token, presented_token(req));
      std::make_shared<WsSession>(stream_.release_socket(), impl_, std::move(slot_), may_control,
                                  peer_)
          ->run(parser_->release());
      return;
    }
    response_ = impl_.handle_http(req, peer_);
    write();
  }
  void write() {
    stream_.expires_after(seconds(impl_.options.write_stall_timeout_s));
    http::async_write(
        stream_, response_,
        [self = shared_from_this()](const boost::system::error_code& wec, std::size_t) {
          if (wec) return;
          if (self->response_.keep_alive()) {
            self->read();
          } else {
            boost::system::error_code ignored;
            self->stream_.socket().shutdown(tcp::socket::shutdown_send, ignored);
          }
        });
  }
  static constexpr std::uint32_t kMaxHeaderBytes = 8192;
  beast::tcp_stream stream_;
  beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::string_body>> parser_;
  http::response<http::string_body> response_;
  Impl& impl_;
  TcpSlot slot_;
  bool loopback_ = false;
  std::string peer_;
};

void LiveServer::Impl::emit_log(fox::LogLevel level, const std::string& text) {
  std::vector<std::uint32_t> subs;
  std::string payload;
  const core::TimeNs now = clock.now_ns();
  for (const auto& weak : clients) {
    const auto client = weak.lock();
    if (!client || !client->open()) continue;
    client->subscriptions_of(kLog, subs);
    if (subs.empty()) continue;
    const core::TimeNs utc = now + utc_offset_ns;
    if (payload.empty()) payload = fox::log_json(utc, level, "coxswain.live", text);
    for (std::uint32_t sub : subs) client->send(message_data(sub, utc, payload), true);
  }
}

void LiveServer::Impl::on_viz_timer() {
  std::erase_if(clients, [](const std::weak_ptr<WsSession>& w) {
    const auto c = w.lock();
    return !c || !c->open();
  });
  const std::uint64_t applied = applied_request.load();
  for (const auto& weak : clients) {
    if (const auto c = weak.lock()) c->answer_applied(applied);
  }
  const auto any_subscribed = [&](std::uint32_t channel) {
    for (const auto& weak : clients) {
      const auto c = weak.lock();
      if (c && c->subscribed(channel)) return true;
    }
    return false;
  };
  std::vector<std::uint32_t> subs;
  const auto broadcast = [&](std::uint32_t channel, core::TimeNs stamp_ns,
                             const std::string& payload) {
    for (const auto& weak : clients) {
      const auto c = weak.lock();
      if (!c) continue;
      c->subscriptions_of(channel, subs);
      for (std::uint32_t sub : subs) c->send(message_data(sub, stamp_ns, payload), true);
    }
  };
  if (tick_slot.sequence() != sent_tick_seq) {
    const core::Sample<LiveTick> t = tick_slot.read();
    sent_tick_seq = t.sequence;
    if (t.value.viz.pose_valid) track.add({t.value.viz.north_m, t.value.viz.east_m});
    const core::TimeNs utc = t.stamp_ns + utc_offset_ns;
    if (any_subscribed(kTf)) broadcast(kTf, utc, fox::frame_transform_json(utc, t.value.viz));
    if (any_subscribed(kScene)) {
      broadcast(kScene, utc,
                fox::scene_update_json(utc, t.value.viz, t.value.summary.status.state_path.view()));
    }
  }
  if (!clients.empty()) {
    std::size_t map_subs = 0;
    for (const auto& weak : clients) {
      if (const auto c = weak.lock()) {
        c->subscriptions_of(kMap, subs);
        map_subs += subs.size();
        c->subscriptions_of(kGeoJson, subs);
        map_subs += subs.size();
      }
    }
    const core::TimeNs now = clock.now_ns();
    // A new subscriber gets the map now (it is sent to all: small, and rare).
    if (map_subs > 0 &&
        (map_subs > map_subscriptions || now - last_map_ns >= options.map_period_ns)) {
      last_map_ns = now;
      const core::TimeNs utc = now + utc_offset_ns;
      broadcast(kMap, utc, fox::map_scene_json(utc, options.map, track.points()));
      broadcast(kGeoJson, utc, fox::geojson_json(options.map));
    }
    map_subscriptions = map_subs;
    if (any_subscribed(kImage) || any_subscribed(kAnnotations)) {
      {
        const std::lock_guard<std::mutex> lock(image_mutex);
        if (image.sequence != sent_image_seq) {
          image_copy.sequence = image.sequence;
          image_copy.stamp_ns = image.stamp_ns;
          image_copy.jpeg.assign(image.jpeg.begin(), image.jpeg.end());
          image_copy.detections = image.detections;
          image_copy.scale = image.scale;
        }
      }
      if (image_copy.sequence != sent_image_seq) {
        sent_image_seq = image_copy.sequence;
        const core::TimeNs utc = image_copy.stamp_ns + utc_offset_ns;
        if (any_subscribed(kImage)) {
          broadcast(kImage, utc, fox::compressed_image_json(utc, image_copy.jpeg));
        }
        if (any_subscribed(kAnnotations)) {
          broadcast(kAnnotations, utc,
                    fox::image_annotations_json(utc, image_copy.detections, image_copy.scale));
        }
      }
    }
    if (store.lidar.sequence() != sent_scan_seq && any_subscribed(kScan)) {
      store.lidar.read(*scan);
      sent_scan_seq = scan->sequence;
      scan->value.stamp_ns += utc_offset_ns;  // our copy
      broadcast(kScan, scan->stamp_ns + utc_offset_ns, fox::laser_scan_json(scan->value));
    }
    if (store.gnss.sequence() != sent_fix_seq && any_subscribed(kFix)) {
      core::Sample<msg::GnssFix> fix = store.gnss.read();
      sent_fix_seq = fix.sequence;
      fix.value.stamp_ns += utc_offset_ns;
      broadcast(kFix, fix.stamp_ns + utc_offset_ns, fox::location_fix_json(fix.value));
    }
  }
  arm_viz_timer();
}

void LiveServer::Impl::sweep() {
  const auto now = std::chrono::steady_clock::now();
  for (const auto& weak : clients) {
    if (const auto c = weak.lock()) c->sweep(now);
  }
  std::erase_if(clients, [](const std::weak_ptr<WsSession>& w) {
    const auto c = w.lock();
    return !c || !c->open();
  });
#if defined(__GLIBC__)
  if (trim_memory) ::malloc_trim(0);  // a dropped client's queue back to the system
#endif
  trim_memory = false;
  sweep_timer.expires_after(std::chrono::seconds(1));
  sweep_timer.async_wait([this](const boost::system::error_code& ec) {
    if (!ec) sweep();
  });
}

void LiveServer::Impl::control_sweep() {
  const auto now = std::chrono::steady_clock::now();
  for (const auto& weak : control_sessions) {
    const auto c = weak.lock();
    if (c && c->open() && now - c->last_activity() > seconds(options.idle_timeout_s)) c->close();
  }
  std::erase_if(control_sessions, [](const std::weak_ptr<ControlSession>& w) {
    const auto c = w.lock();
    return !c || !c->open();
  });
  control_sweep_timer.expires_after(std::chrono::seconds(1));
  control_sweep_timer.async_wait([this](const boost::system::error_code& ec) {
    if (!ec) control_sweep();
  });
}

void LiveServer::Impl::accept_unix() {
  unix_acceptor.async_accept([this](const boost::system::error_code& ec,
                                    local_stream::socket socket) {
    if (ec == asio::error::operation_aborted) return;
    if (ec) {
      // Out of descriptors (or another accept failure): back off instead of spinning.
      warn_limited(control_accept_limiter, "live: control socket accept failed: " + ec.message());
      unix_retry_timer.expires_after(std::chrono::milliseconds(resource_exhausted(ec) ? 100 : 10));
      unix_retry_timer.async_wait([this](const boost::system::error_code& tec) {
        if (!tec) accept_unix();
      });
      return;
    }
    // The operator's `ctl hold` always gets in: the oldest connection gives way.
    std::erase_if(control_sessions, [](const std::weak_ptr<ControlSession>& w) {
      const auto c = w.lock();
      return !c || !c->open();
    });
    while (!control_sessions.empty() &&
           control_sessions.size() >= options.max_control_connections) {
      if (const auto oldest = control_sessions.front().lock()) oldest->close();
      control_sessions.erase(control_sessions.begin());
    }
    auto session = std::make_shared<ControlSession>(std::move(socket), *this);
    control_sessions.push_back(session);
    session->read();
    accept_unix();
  });
}

void LiveServer::Impl::accept_tcp() {
  tcp_acceptor.async_accept([this](const boost::system::error_code& ec, tcp::socket socket) {
    if (ec == asio::error::operation_aborted) return;
    if (ec) {
      warn_limited(accept_limiter, "live: HTTP accept failed: " + ec.message());
      tcp_retry_timer.expires_after(std::chrono::milliseconds(resource_exhausted(ec) ? 100 : 10));
      tcp_retry_timer.async_wait([this](const boost::system::error_code& tec) {
        if (!tec) accept_tcp();
      });
      return;
    }
    if (tcp_connections >= max_tcp) {
      // Closed at once: the descriptor goes back, the backlog keeps draining.
      boost::system::error_code ignored;
      const tcp::endpoint remote = socket.remote_endpoint(ignored);
      warn_limited(refused_limiter, "live: refused a connection from " +
                                        remote.address().to_string() + ": " +
                                        std::to_string(max_tcp) + " connections are open");
      socket.close(ignored);
    } else {
      std::make_shared<HttpSession>(std::move(socket), *this, TcpSlot(*this))->read();
    }
    accept_tcp();
  });
}

LiveServer::LiveServer(LiveOptions options, core::LatestStore& store, const core::Clock& clock)
    : impl_(std::make_unique<Impl>(std::move(options), store, clock)) {}

LiveServer::~LiveServer() { stop(); }

bool LiveServer::start(std::string& error) {
  Impl& m = *impl_;
  if (m.started) return true;
  if (!(m.options.viz_rate_hz > 0.0)) {
    error = "viz_rate_hz must be > 0";
    return false;
  }
  m.utc_offset_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
                        std::chrono::system_clock::now().time_since_epoch())
                        .count() -
                    m.clock.now_ns();
  boost::system::error_code ec;
  if (!m.options.socket_path.empty()) {
    std::error_code fec;
    std::filesystem::create_directories(m.options.socket_path.parent_path(), fec);
    std::filesystem::remove(m.options.socket_path, fec);  // a stale socket of an earlier run
    // The endpoint constructor throws on a path longer than sun_path: check first.
    if (m.options.socket_path.string().size() >= sizeof(sockaddr_un::sun_path)) {
      error = "control socket " + m.options.socket_path.string() + ": path longer than " +
              std::to_string(sizeof(sockaddr_un::sun_path) - 1) + " bytes";
      return false;
    }
    const local_stream::endpoint ep(m.options.socket_path.string());
    if (m.unix_acceptor.open(ep.protocol(), ec) || m.unix_acceptor.bind(ep, ec) ||
        m.unix_acceptor.listen(asio::socket_base::max_listen_connections, ec)) {
      error = "control socket " + m.options.socket_path.string() + ": " + ec.message();
      m.unix_acceptor.close(ec);
      return false;
    }
    m.socket_bound = true;
    ::chmod(m.options.socket_path.c_str(), 0660);  // owner and group (the operators) only
  }
  if (m.options.http_enabled) {
    const asio::ip::address address = asio::ip::make_address(m.options.http_address, ec);
    if (ec) {
      error = "http_address '" + m.options.http_address + "': " + ec.message();
      stop();
      return false;
    }
    const tcp::endpoint ep(address, m.options.http_port);
    if (m.tcp_acceptor.open(ep.protocol(), ec) ||
        m.tcp_acceptor.set_option(asio::socket_base::reuse_address(true), ec) ||
        m.tcp_acceptor.bind(ep, ec) ||
        m.tcp_acceptor.listen(asio::socket_base::max_listen_connections, ec)) {
      error = "live view on " + m.options.http_address + ":" + std::to_string(m.options.http_port) +
              ": " + ec.message();
      m.tcp_acceptor.close(ec);
      stop();
      return false;
    }
    m.port.store(m.tcp_acceptor.local_endpoint(ec).port());
  }
  if (m.options.initial_target_colour != msg::Colour::kUnknown ||
      m.options.initial_target_shape != msg::Shape::kUnknown) {
    // Before the thread exists, so the control thread stays the slot's only writer.
    m.publish_operator(m.operator_state.apply(
        {CommandKind::kTarget, m.options.initial_target_colour, m.options.initial_target_shape},
        m.clock.now_ns()));
  }
  m.max_tcp = m.options.max_http_connections;
  rlimit nofile{};
  if (::getrlimit(RLIMIT_NOFILE, &nofile) == 0 && nofile.rlim_cur != RLIM_INFINITY) {
    const std::size_t cur = nofile.rlim_cur;
    const std::size_t room = cur > m.options.fd_reserve ? (cur - m.options.fd_reserve) / 2 : 0;
    m.max_tcp = std::max<std::size_t>(1, std::min(m.max_tcp, room));
  }
  if (m.options.max_control_connections == 0) m.options.max_control_connections = 1;
  if (m.unix_acceptor.is_open()) {
    m.accept_unix();
    m.control_sweep();
  }
  if (m.tcp_acceptor.is_open()) m.accept_tcp();
  m.arm_viz_timer();
  m.sweep();
  m.started = true;
  m.thread = std::thread([&m] { m.ioc.run(); });
  m.control_thread = std::thread([&m] { m.control_ioc.run(); });
  return true;
}

void LiveServer::stop() {
  Impl& m = *impl_;
  if (m.control_thread.joinable()) {
    m.control_ioc.stop();
    m.control_thread.join();
  }
  if (m.thread.joinable()) {
    m.ioc.stop();
    m.thread.join();
  }
  boost::system::error_code ec;
  m.unix_acceptor.close(ec);
  m.tcp_acceptor.close(ec);
  if (m.socket_bound) {
    std::error_code fec;
    std::filesystem::remove(m.options.socket_path, fec);
    m.socket_bound = false;
  }
  m.port.store(0);
  m.started = false;
}

std::uint16_t LiveServer::http_port() const { return impl_->port.load(); }

void LiveServer::publish_image(core::TimeNs stamp_ns, std::span<const std::uint8_t> jpeg,
                               const msg::CameraDetections& detections, double scale) {
  const std::lock_guard<std::mutex> lock(impl_->image_mutex);
  Impl::Image& i = impl_->image;
  i.jpeg.assign(jpeg.begin(), jpeg.end());
  i.stamp_ns = stamp_ns;
  i.detections = detections;
  i.scale = scale;
  ++i.sequence;
}

void LiveServer::publish_tick(const LiveTick& tick, core::TimeNs now_ns) {
  impl_->tick_slot.publish(tick, now_ns);
}

void LiveServer::publish_parameters(const mission::TunableParameters& in_force,
                                    core::TimeNs now_ns) {
  impl_->in_force_slot.publish(in_force, now_ns);
  impl_->applied_request.store(impl_->consumed_request);
}

bool LiveServer::take_parameters(mission::TunableParameters& out) {
  Impl& m = *impl_;
  const std::uint64_t seq = m.requested_slot.sequence();
  if (seq == m.consumed_request) return false;
  const core::Sample<mission::TunableParameters> s = m.requested_slot.read();
  m.consumed_request = s.sequence;
  out = s.value;
  return true;
}

}  // namespace coxswain::live
