// SPDX-License-Identifier: Apache-2.0
// LiveServer over its real sockets: the control socket (line commands), the status page and its
// token-protected API over HTTP, and the Foxglove WebSocket protocol (serverInfo, advertise,
// subscribe, messageData, parameters), with a thread standing in for the tick thread.
#include "coxswain/live/live_server.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <chrono>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <thread>

#include "coxswain/core/clock.hpp"
#include "coxswain/live/control_client.hpp"
#include "coxswain/live/request_guard.hpp"
#include "coxswain/mission/tunable_parameters.hpp"

namespace coxswain::live {
namespace {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;
using nlohmann::json;
namespace fs = std::filesystem;

constexpr const char* kToken = "correct-horse";

/// A Foxglove WebSocket client of the test server, connected: the serverInfo and advertise
/// messages read and kept.
class FoxgloveClient {
 public:
  FoxgloveClient(std::unique_ptr<asio::io_context> ioc,
                 std::unique_ptr<websocket::stream<tcp::socket>> ws)
      : ioc_(std::move(ioc)), ws_(std::move(ws)) {
    info = json::parse(next().second);
    advertise = json::parse(next().second);
    ws_->text(true);
  }
  /// The next message: whether it is binary, and its bytes.
  std::pair<bool, std::string> next() {
    buf_.clear();
    ws_->read(buf_);
    return {ws_->got_binary(), beast::buffers_to_string(buf_.data())};
  }
  void send(const json& message) { ws_->write(asio::buffer(message.dump())); }
  void close() { ws_->close(websocket::close_code::normal); }
  /// The advertised channel of `topic`, 0 when none.
  [[nodiscard]] std::uint32_t channel(std::string_view topic) const {
    for (const auto& c : advertise["channels"]) {
      if (c["topic"] == topic) return c["id"].get<std::uint32_t>();
    }
    return 0;
  }
  json info;
  json advertise;

 private:
  std::unique_ptr<asio::io_context> ioc_;
  std::unique_ptr<websocket::stream<tcp::socket>> ws_;
  beast::flat_buffer buf_;
};

class LiveServerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("coxswain_live_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    store_ = std::make_unique<core::LatestStore>();
    restart(options());
  }
  LiveOptions options() const {
    LiveOptions o;
    o.socket_path = dir_ / "control.sock";
    o.http_port = 0;
    o.viz_rate_hz = 20.0;
    o.token = kToken;
    o.initial_target_colour = msg::Colour::kRed;
    o.initial_target_shape = msg::Shape::kTriangle;
    return o;
  }
  void restart(const LiveOptions& o) {
    stop_tick();
    stop_.store(false);
    server_.reset();
    server_ = std::make_unique<LiveServer>(o, *store_, clock_);
    std::string error;
    ASSERT_TRUE(server_->start(error)) << error;
    ASSERT_NE(server_->http_port(), 0);
  }
  void TearDown() override {
    stop_tick();
    server_.reset();
    fs::remove_all(dir_);
  }

  // Stands in for the daemon's tick thread: publishes ticks, applies parameter requests.
  void start_tick() {
    tick_thread_ = std::thread([this] {
      LiveTick t;
      mission::TunableParameters in_force;
      server_->publish_parameters(in_force, clock_.now_ns());
      std::uint64_t i = 0;
      while (!stop_.load()) {
        mission::TunableParameters requested;
        if (server_->take_parameters(requested)) {
          in_force = requested;
          if (adjust_) adjust_(in_force);  // as the core may limit what it is given
          server_->publish_parameters(in_force, clock_.now_ns());
        }
        t.summary.tick_index = ++i;
        t.summary.status.state_path.assign("wait_for_start");
        t.viz.pose_valid = true;
        t.viz.north_m = 1.0 + 0.05 * static_cast<double>(i);  // 10 m/s north: a track
        t.viz.east_m = 2.0;
        server_->publish_tick(t, clock_.now_ns());
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
      }
    });
  }
  void stop_tick() {
    stop_.store(true);
    if (tick_thread_.joinable()) tick_thread_.join();
  }

  std::string ctl(const std::string& line) {
    std::string error;
    const auto answer = send_control_command(dir_ / "control.sock", line, error);
    EXPECT_TRUE(answer) << error;
    return answer.value_or("");
  }

  http::response<http::string_body> request(http::verb verb, const std::string& target,
                                            const std::string& token = "",
                                            const std::string& body = "",
                                            const std::string& host = "127.0.0.1",
                                            const std::string& origin = "") {
    asio::io_context ioc;
    beast::tcp_stream stream(ioc);
    stream.connect(tcp::endpoint(asio::ip::make_address("127.0.0.1"), server_->http_port()));
    http::request<http::string_body> req{verb, target, 11};
    req.set(http::field::host, host);
    if (!origin.empty()) req.set(http::field::origin, origin);
    if (!token.empty()) req.set("X-Coxswain-Token", token);
    req.body() = body;
    req.prepare_payload();
    http::write(stream, req);
    beast::flat_buffer buffer;
    http::response<http::string_body> res;
    http::read(stream, buffer, res);
    return res;
  }

  // A Foxglove client; `origin` empty: none sent (not a browser).
  std::unique_ptr<websocket::stream<tcp::socket>> connect_ws(
      asio::io_context& ioc, const std::string& target, const std::string& origin,
      boost::system::error_code& ec, websocket::response_type* response = nullptr) {
    auto ws = std::make_unique<websocket::stream<tcp::socket>>(ioc);
    ws->next_layer().connect(
        tcp::endpoint(asio::ip::make_address("127.0.0.1"), server_->http_port()));
    ws->set_option(websocket::stream_base::decorator([origin](websocket::request_type& req) {
      req.set(http::field::sec_websocket_protocol, "foxglove.websocket.v1");
      if (!origin.empty()) req.set(http::field::origin, origin);
    }));
    const std::string host = "127.0.0.1:" + std::to_string(server_->http_port());
    if (response != nullptr) {
      ws->handshake(*response, host, target, ec);
    } else {
      ws->handshake(host, target, ec);
    }
    return ws;
  }
  // A Foxglove client with the token, past serverInfo and advertise.
  std::unique_ptr<FoxgloveClient> foxglove_client() {
    auto ioc = std::make_unique<asio::io_context>();
    boost::system::error_code ec;
    websocket::response_type handshake;
    auto ws = connect_ws(*ioc, std::string("/?token=") + kToken, "", ec, &handshake);
    EXPECT_FALSE(ec) << ec.message();
    EXPECT_EQ(handshake[http::field::sec_websocket_protocol], "foxglove.websocket.v1");
    return std::make_unique<FoxgloveClient>(std::move(ioc), std::move(ws));
  }
  // The next text message (skipping visualization frames).
  static json next_text(websocket::stream<tcp::socket>& ws) {
    beast::flat_buffer buf;
    for (;;) {
      buf.clear();
      ws.read(buf);
      if (ws.got_text()) return json::parse(beast::buffers_to_string(buf.data()));
    }
  }

  fs::path dir_;
  core::SteadyClock clock_;
  std::unique_ptr<core::LatestStore> store_;
  std::unique_ptr<LiveServer> server_;
  std::thread tick_thread_;
  std::atomic<bool> stop_{false};
  std::function<void(mission::TunableParameters&)> adjust_;  // set before start_tick()
};

// The next parameterValues answer with this id (status messages before it are collected).
json answer_with_id(websocket::stream<tcp::socket>& ws, const std::string& id,
                    std::vector<json>* statuses = nullptr) {
  for (;;) {
    beast::flat_buffer buf;
    ws.read(buf);
    if (!ws.got_text()) continue;
    json j = json::parse(beast::buffers_to_string(buf.data()));
    if (j["op"] == "status" && statuses != nullptr) statuses->push_back(j);
    if (j["op"] == "parameterValues" && j.value("id", std::string()) == id) return j;
  }
}

json value_of(const json& answer, const std::string& name) {
  for (const auto& p : answer["parameters"]) {
    if (p["name"] == name) return p["value"];
  }
  return nullptr;
}

// Parameters are refused ("not running yet") and read back empty until the core's first tick
// has published them: a test that starts its tick thread waits for that before using them.
bool wait_for_first_tick(websocket::stream<tcp::socket>& ws) {
  for (int i = 0; i < 500; ++i) {
    ws.write(asio::buffer(json{
        {"op", "getParameters"}, {"id", "ready"}, {"parameterNames", {"heading_pid.kp_per_deg"}}}
                              .dump()));
    if (!value_of(answer_with_id(ws, "ready"), "heading_pid.kp_per_deg").is_null()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return false;
}

TEST_F(LiveServerTest, ControlSocketCommandsReachTheStore) {
  struct stat st {};
  ASSERT_EQ(::stat((dir_ / "control.sock").c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777U, 0660U);
  // The initial target (--target) is published at start.
  EXPECT_EQ(store_->operator_input.read().value.target_colour, msg::Colour::kRed);

  EXPECT_TRUE(answer_ok(ctl("start")));
  EXPECT_EQ(store_->operator_input.read().value.start_count, 1U);
  EXPECT_TRUE(answer_ok(ctl("hold")));
  EXPECT_TRUE(store_->operator_input.read().value.hold);
  EXPECT_TRUE(answer_ok(ctl("resume")));
  EXPECT_FALSE(store_->operator_input.read().value.hold);
  EXPECT_EQ(store_->operator_input.read().value.hold_count, 2U);
  EXPECT_TRUE(answer_ok(ctl("target blue circle")));
  EXPECT_EQ(store_->operator_input.read().value.target_shape, msg::Shape::kCircle);

  const std::string bad = ctl("launch");
  EXPECT_FALSE(answer_ok(bad));
  EXPECT_NE(bad.find("unknown command"), std::string::npos);

  const json status = json::parse(ctl("status"));
  EXPECT_EQ(status["state_path"], "starting");  // no tick yet
  EXPECT_EQ(status["operator"]["start_count"], 1);
  EXPECT_EQ(status["operator"]["target_colour"], "blue");

  // Several commands on one connection, answered in order.
  asio::io_context ioc;
  asio::local::stream_protocol::socket s(ioc);
  s.connect(asio::local::stream_protocol::endpoint((dir_ / "control.sock").string()));
  asio::write(s, asio::buffer(std::string("start\nstart\nstatus\n")));
  asio::streambuf buf;
  std::string lines[3];
  for (auto& l : lines) {
    asio::read_until(s, buf, '\n');
    std::istream is(&buf);
    std::getline(is, l);
  }
  EXPECT_EQ(json::parse(lines[2])["operator"]["start_count"], 3);
}

TEST_F(LiveServerTest, StatusPageAndTokenProtectedButtons) {
  start_tick();
  const auto page = request(http::verb::get, "/");
  EXPECT_EQ(page.result(), http::status::ok);
  EXPECT_NE(page.body().find("<!DOCTYPE html>"), std::string::npos);
  EXPECT_NE(page.body().find("/api/"), std::string::npos);

  for (int i = 0; i < 200; ++i) {
    const auto st = request(http::verb::get, "/api/status");
    ASSERT_EQ(st.result(), http::status::ok);
    if (json::parse(st.body())["state_path"] == "wait_for_start") break;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  EXPECT_EQ(json::parse(request(http::verb::get, "/api/status").body())["state_path"],
            "wait_for_start");

  EXPECT_EQ(request(http::verb::post, "/api/start").result(), http::status::unauthorized);
  EXPECT_EQ(request(http::verb::post, "/api/start", "correct-horsE").result(),
            http::status::unauthorized);
  EXPECT_EQ(store_->operator_input.read().value.start_count, 0U);
  EXPECT_EQ(request(http::verb::post, "/api/start", kToken).result(), http::status::ok);
  EXPECT_EQ(store_->operator_input.read().value.start_count, 1U);
  EXPECT_EQ(request(http::verb::post, "/api/hold", kToken).result(), http::status::ok);
  EXPECT_TRUE(store_->operator_input.read().value.hold);
  EXPECT_EQ(request(http::verb::post, "/api/target", kToken,
                    R"({"colour": "green", "shape": "rectangle"})")
                .result(),
            http::status::ok);
  EXPECT_EQ(store_->operator_input.read().value.target_colour, msg::Colour::kGreen);
  EXPECT_EQ(request(http::verb::post, "/api/target", kToken, "not json").result(),
            http::status::bad_request);
  EXPECT_EQ(request(http::verb::get, "/api/start", kToken).result(),
            http::status::method_not_allowed);
  EXPECT_EQ(request(http::verb::get, "/nowhere").result(), http::status::not_found);
}

TEST_F(LiveServerTest, TheMapIsSentAtOnceToANewSubscriberAndAgainWithTheTrack) {
  LiveOptions o = options();
  o.map.marks.push_back({record::MapMark::Kind::kWaypoint, "hopping 1", {35.1, 129.0, {9.0, 1.0}}});
  o.map_period_ns = 100 * core::kNsPerMs;
  restart(o);
  start_tick();
  const auto client = foxglove_client();
  const std::uint32_t map_channel = client->channel("/viz/map");
  const std::uint32_t geojson_channel = client->channel("/map/geojson");
  ASSERT_NE(map_channel, 0U);
  ASSERT_NE(geojson_channel, 0U);
  client->send(json{
      {"op", "subscribe"},
      {"subscriptions",
       {{{"id", 3}, {"channelId", map_channel}}, {{"id", 4}, {"channelId", geojson_channel}}}}});
  bool geojson_seen = false;
  std::size_t longest_track = 0;
  int maps = 0;
  for (int frames = 0; frames < 50 && (maps < 3 || !geojson_seen); ++frames) {
    auto [binary, frame] = client->next();
    if (!binary) continue;
    ASSERT_GT(frame.size(), 13U);
    const auto m = json::parse(frame.substr(13));
    if (frame[1] == 4) {
      geojson_seen = m["geojson"].get<std::string>().find("hopping 1") != std::string::npos;
      continue;
    }
    ASSERT_EQ(frame[1], 3);
    ++maps;
    EXPECT_EQ(m["entities"][0]["texts"][0]["text"], "hopping 1");
    const auto& lines = m["entities"][1]["lines"];
    if (!lines.empty()) longest_track = std::max(longest_track, lines[0]["points"].size());
  }
  EXPECT_TRUE(geojson_seen);
  EXPECT_GE(maps, 3);            // at once, then every period
  EXPECT_GE(longest_track, 2U);  // the boat moved: the track is a line
}

TEST_F(LiveServerTest, TheNewestCameraImageAndItsDetectionsGoToSubscribers) {
  const auto client = foxglove_client();
  const std::uint32_t image_channel = client->channel("/camera/image");
  const std::uint32_t notes_channel = client->channel("/camera/annotations");
  ASSERT_NE(image_channel, 0U);
  ASSERT_NE(notes_channel, 0U);
  client->send(json{
      {"op", "subscribe"},
      {"subscriptions",
       {{{"id", 5}, {"channelId", image_channel}}, {{"id", 6}, {"channelId", notes_channel}}}}});
  const std::vector<std::uint8_t> jpeg{0xFF, 0xD8, 0xFF, 0xE0, 0x01, 0x02};
  msg::CameraDetections d;
  ASSERT_TRUE(d.push(
      {msg::Colour::kYellow, msg::Shape::kCross, 0.0F, 10.0F, 10.0F, 4.0F, 4.0F, 16.0F, 0.7F}));
  server_->publish_image(42, jpeg, d, 1.0);
  json image;
  json notes;
  for (int frames = 0; frames < 20 && (image.is_null() || notes.is_null()); ++frames) {
    auto [binary, frame] = client->next();
    if (!binary) continue;
    ASSERT_GT(frame.size(), 13U);
    (frame[1] == 5 ? image : notes) = json::parse(frame.substr(13));
  }
  ASSERT_FALSE(image.is_null());
  ASSERT_FALSE(notes.is_null());
  EXPECT_EQ(image["format"], "jpeg");
  EXPECT_EQ(image["data"], "/9j/4AEC");  // the six bytes, base64
  EXPECT_EQ(notes["texts"][0]["text"], "yellow cross 0.70");
}

TEST_F(LiveServerTest, FoxgloveSubscribeReceiveAndSetParameters) {
  start_tick();
  const auto client = foxglove_client();
  const auto next = [&client] { return client->next(); };
  const json& info = client->info;
  EXPECT_EQ(info["op"], "serverInfo");
  EXPECT_EQ(info["capabilities"], json::array({"parameters"}));
  const json& adv = client->advertise;
  ASSERT_EQ(adv["op"], "advertise");
  std::uint32_t tf_channel = 0;
  for (const auto& c : adv["channels"]) {
    EXPECT_EQ(c["encoding"], "json");
    EXPECT_EQ(c["schemaEncoding"], "jsonschema");
    if (c["topic"] == "/tf") tf_channel = c["id"];
  }
  ASSERT_NE(tf_channel, 0U);
  client->send(
      json{{"op", "subscribe"}, {"subscriptions", {{{"id", 7}, {"channelId", tf_channel}}}}});
  auto [binary, frame] = next();
  ASSERT_TRUE(binary);
  ASSERT_GT(frame.size(), 13U);
  EXPECT_EQ(frame[0], 0x01);
  EXPECT_EQ(static_cast<unsigned char>(frame[1]), 7U);  // subscription id, little-endian
  const auto tf = json::parse(frame.substr(13));
  EXPECT_EQ(tf["parent_frame_id"], "map");
  // Stamps are wall-clock (UTC) times, in the message and in its messageData header.
  const auto utc_now_s = std::chrono::duration_cast<std::chrono::seconds>(
                             std::chrono::system_clock::now().time_since_epoch())
                             .count();
  EXPECT_NEAR(tf["timestamp"]["sec"].get<double>(), static_cast<double>(utc_now_s), 60.0);
  std::uint64_t header_ns = 0;
  for (int i = 7; i >= 0; --i) {
    header_ns =
        (header_ns << 8U) | static_cast<unsigned char>(frame[5 + static_cast<std::size_t>(i)]);
  }
  EXPECT_NEAR(static_cast<double>(header_ns) / 1e9, static_cast<double>(utc_now_s), 60.0);
  EXPECT_DOUBLE_EQ(tf["translation"]["x"].get<double>(), 2.0);  // east

  client->send(json{{"op", "unsubscribe"}, {"subscriptionIds", {7}}});
  client->send(json{{"op", "setParameters"},
                    {"id", "s1"},
                    {"parameters", {{{"name", "heading_pid.kp_per_deg"}, {"value", 0.07}}}}});
  // Skip frames still in flight from before the unsubscribe.
  json reply;
  do {
    auto [b, text] = next();
    if (!b) reply = json::parse(text);
  } while (reply.is_null());
  EXPECT_EQ(reply["op"], "parameterValues");
  EXPECT_EQ(reply["id"], "s1");
  // The tick stand-in applies it; getParameters reports what is in force.
  bool applied = false;
  for (int i = 0; i < 200 && !applied; ++i) {
    client->send(
        json{{"op", "getParameters"}, {"id", "g"}, {"parameterNames", {"heading_pid.kp_per_deg"}}});
    json values;
    do {
      auto [b, text] = next();
      if (!b) values = json::parse(text);
    } while (values.is_null());
    ASSERT_EQ(values["op"], "parameterValues");
    applied = values["parameters"][0]["value"].get<double>() == 0.07;
    if (!applied) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EXPECT_TRUE(applied);

  client->send(json{{"op", "setParameters"},
                    {"id", "s2"},
                    {"parameters", {{{"name", "heading_pid.kp_per_deg"}, {"value", 9.0}}}}});
  json st;
  do {
    auto [b, text] = next();
    if (!b) st = json::parse(text);
  } while (st.is_null());
  EXPECT_EQ(st["op"], "status");
  EXPECT_EQ(st["level"], 2);
  EXPECT_NE(st["message"].get<std::string>().find("kp_per_deg"), std::string::npos);
  client->close();
}

TEST_F(LiveServerTest, SetParametersWithoutTheTokenIsRefusedAndChangesNothing) {
  start_tick();
  asio::io_context ioc;
  boost::system::error_code ec;
  for (const std::string target : {"/", "/?token=correct-horsE", "/?token="}) {
    auto ws = connect_ws(ioc, target, "", ec);
    ASSERT_FALSE(ec) << ec.message();  // viewing from this computer stays open
    EXPECT_EQ(next_text(*ws)["op"], "serverInfo");
    EXPECT_EQ(next_text(*ws)["op"], "advertise");
    ws->text(true);
    ws->write(
        asio::buffer(json{{"op", "setParameters"},
                          {"id", "x"},
                          {"parameters", {{{"name", "heading_pid.kp_per_deg"}, {"value", 0.0}}}}}
                         .dump()));
    const json st = next_text(*ws);
    EXPECT_EQ(st["op"], "status");
    EXPECT_EQ(st["level"], 2);
    EXPECT_NE(st["message"].get<std::string>().find("needs the token"), std::string::npos)
        << st.dump();
    ws->write(asio::buffer(json{{"op", "getParameters"}, {"id", "g"}}.dump()));
    const json values = next_text(*ws);
    ASSERT_EQ(values["op"], "parameterValues");
    for (const auto& p : values["parameters"]) {
      if (p["name"] == "heading_pid.kp_per_deg") {
        EXPECT_NE(p["value"].get<double>(), 0.0);
      }
    }
  }
}

TEST_F(LiveServerTest, AnEmptyTokenDisablesLiveTuningWithAClearMessage) {
  LiveOptions o = options();
  o.token.clear();
  restart(o);
  start_tick();
  asio::io_context ioc;
  boost::system::error_code ec;
  auto ws = connect_ws(ioc, "/?token=", "", ec);
  ASSERT_FALSE(ec) << ec.message();
  ws->text(true);
  ws->write(
      asio::buffer(json{{"op", "setParameters"},
                        {"parameters", {{{"name", "heading_pid.kp_per_deg"}, {"value", 0.0}}}}}
                       .dump()));
  json st;
  do {
    st = next_text(*ws);
  } while (st["op"] != "status");
  EXPECT_NE(st["message"].get<std::string>().find("no token is configured"), std::string::npos);
  EXPECT_EQ(request(http::verb::post, "/api/hold", "").result(), http::status::unauthorized);
  EXPECT_NE(request(http::verb::post, "/api/hold", "").body().find("no token is configured"),
            std::string::npos);
}

TEST_F(LiveServerTest, ACrossOriginWebSocketIsRefusedEvenWithTheToken) {
  asio::io_context ioc;
  boost::system::error_code ec;
  connect_ws(ioc, std::string("/?token=") + kToken, "http://evil.example", ec);
  EXPECT_TRUE(ec) << "the handshake succeeded";
  ec.clear();
  auto same = connect_ws(ioc, "/", "http://127.0.0.1:" + std::to_string(server_->http_port()), ec);
  EXPECT_FALSE(ec) << "same-origin page refused: " << ec.message();
  ec.clear();
  auto foxglove = connect_ws(ioc, "/", "https://app.foxglove.dev", ec);
  EXPECT_FALSE(ec) << "the Foxglove web app refused: " << ec.message();
}

TEST_F(LiveServerTest, ARebindingHostOrForeignOriginIsRefused) {
  EXPECT_EQ(request(http::verb::get, "/api/status", "", "", "evil.example:8765").result(),
            http::status::forbidden);
  EXPECT_EQ(request(http::verb::post, "/api/hold", kToken, "", "evil.example").result(),
            http::status::forbidden);
  EXPECT_EQ(request(http::verb::post, "/api/hold", kToken, "", "127.0.0.1", "http://evil.example")
                .result(),
            http::status::forbidden);
  EXPECT_FALSE(store_->operator_input.read().value.hold);
  EXPECT_EQ(request(http::verb::get, "/api/status", "", "", "localhost:1234").result(),
            http::status::ok);
  EXPECT_EQ(request(http::verb::post, "/api/hold", kToken, "", "[::1]:8765").result(),
            http::status::ok);
  LiveOptions o = options();
  o.allowed_hosts = {"boat.local"};
  restart(o);
  EXPECT_EQ(request(http::verb::get, "/api/status", "", "", "Boat.Local:8765").result(),
            http::status::ok);
}

TEST_F(LiveServerTest, ConnectionsBeyondTheLimitAreClosedAndControlStillAnswers) {
  LiveOptions o = options();
  o.max_http_connections = 8;
  o.max_control_connections = 4;
  restart(o);
  asio::io_context ioc;
  std::vector<std::unique_ptr<tcp::socket>> idle;
  for (int i = 0; i < 20; ++i) {
    idle.push_back(std::make_unique<tcp::socket>(ioc));
    idle.back()->connect(tcp::endpoint(asio::ip::make_address("127.0.0.1"), server_->http_port()));
  }
  // The twelve beyond the limit are closed by the server: a read ends at once.
  int closed = 0;
  for (auto& s : idle) {
    s->non_blocking(true);
  }
  for (int round = 0; round < 100 && closed < 12; ++round) {
    closed = 0;
    for (auto& s : idle) {
      char c = 0;
      boost::system::error_code ec;
      s->read_some(asio::buffer(&c, 1), ec);
      if (ec == asio::error::eof || ec == asio::error::connection_reset) ++closed;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EXPECT_EQ(closed, 12);
  // Idle control connections give way to the operator.
  std::vector<std::unique_ptr<asio::local::stream_protocol::socket>> ctl_idle;
  for (int i = 0; i < 10; ++i) {
    ctl_idle.push_back(std::make_unique<asio::local::stream_protocol::socket>(ioc));
    ctl_idle.back()->connect(
        asio::local::stream_protocol::endpoint((dir_ / "control.sock").string()));
  }
  EXPECT_TRUE(answer_ok(ctl("hold")));
  EXPECT_TRUE(store_->operator_input.read().value.hold);
}

TEST_F(LiveServerTest, AClientThatDoesNotReadItsRepliesIsDropped) {
  LiveOptions o = options();
  o.max_client_queue_bytes = 64 * 1024;
  restart(o);
  start_tick();
  asio::io_context ioc;
  boost::system::error_code ec;
  auto ws = connect_ws(ioc, "/", "", ec);
  ASSERT_FALSE(ec) << ec.message();
  ws->text(true);
  ws->next_layer().set_option(asio::socket_base::receive_buffer_size(4096));
  const std::string get = json{{"op", "getParameters"}, {"id", "g"}}.dump();
  // Far more replies than the queue and the socket buffers hold; never read. The server works
  // through the requests after they are written: keep writing until it has hung up.
  bool dropped = false;
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  for (int i = 0; !dropped && std::chrono::steady_clock::now() < end; ++i) {
    ws->write(asio::buffer(get), ec);
    dropped = static_cast<bool>(ec);
    if (i > 20000) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  EXPECT_TRUE(dropped) << "the server kept queueing replies";
}

TEST(RequestGuard, HostNamesAndOrigins) {
  EXPECT_EQ(host_name_of("Boat.Local:8765"), "boat.local");
  EXPECT_EQ(host_name_of("[::1]:8765"), "::1");
  EXPECT_EQ(host_name_of("localhost."), "localhost");
  EXPECT_EQ(host_name_of("::1"), "");
  EXPECT_EQ(host_name_of("a b"), "");
  EXPECT_TRUE(host_allowed("127.0.0.1:8765", {}));
  EXPECT_TRUE(host_allowed("192.168.1.20", {}));
  EXPECT_TRUE(host_allowed("[fe80::1]:80", {}));
  EXPECT_TRUE(host_allowed("localhost:8765", {}));
  EXPECT_FALSE(host_allowed("attacker.example", {}));
  EXPECT_FALSE(host_allowed("127.0.0.1.attacker.example", {}));
  EXPECT_FALSE(host_allowed("", {}));
  EXPECT_TRUE(host_allowed("boat.local", {"boat.local"}));
  EXPECT_TRUE(origin_allowed(std::nullopt, "127.0.0.1:8765", {}));
  EXPECT_TRUE(origin_allowed("http://127.0.0.1:8765", "127.0.0.1:8765", {}));
  EXPECT_FALSE(origin_allowed("http://127.0.0.1:9999", "127.0.0.1:8765", {}));
  EXPECT_FALSE(origin_allowed("null", "127.0.0.1:8765", {}));
  EXPECT_TRUE(
      origin_allowed("https://App.Foxglove.dev", "127.0.0.1:8765", {"https://app.foxglove.dev"}));
  EXPECT_EQ(path_of("/api/start?token=x"), "/api/start");
  EXPECT_EQ(query_token("/?a=1&token=abc#frag").value_or("-"), "abc");
  EXPECT_FALSE(query_token("/?tokens=abc"));
}

TEST(RequestGuard, WarningsAreLimitedPerPeriodAndCountTheRest) {
  WarningLimiter limiter(std::chrono::seconds(10));
  const auto t0 = WarningLimiter::Clock::now();
  std::uint64_t suppressed = 99;
  EXPECT_TRUE(limiter.allow(t0, suppressed));
  EXPECT_EQ(suppressed, 0U);
  for (int i = 0; i < 1000; ++i)
    EXPECT_FALSE(limiter.allow(t0 + std::chrono::seconds(5), suppressed));
  EXPECT_TRUE(limiter.allow(t0 + std::chrono::seconds(11), suppressed));
  EXPECT_EQ(suppressed, 1000U);
}

TEST(LiveServerBind, ABusyPortIsReportedNotFatal) {
  core::SteadyClock clock;
  auto store = std::make_unique<core::LatestStore>();
  LiveOptions a;
  a.http_port = 0;
  LiveServer first(a, *store, clock);
  std::string error;
  ASSERT_TRUE(first.start(error)) << error;
  LiveOptions b;
  b.http_port = first.http_port();
  LiveServer second(b, *store, clock);
  EXPECT_FALSE(second.start(error));
  EXPECT_NE(error.find("live view"), std::string::npos) << error;
  b.http_address = "not-an-address";
  LiveServer third(b, *store, clock);
  EXPECT_FALSE(third.start(error));
}

}  // namespace
}  // namespace coxswain::live

namespace coxswain::live {
namespace {

TEST_F(LiveServerTest, ASetIsAnsweredWithTheValueTheTickApplied) {
  adjust_ = [](mission::TunableParameters& p) {
    const mission::TunableSpec* kp = mission::find_tunable("heading_pid.kp_per_deg");
    if (kp->get(p) > 0.05) kp->set(p, 0.05);  // a core that caps the gain
  };
  start_tick();
  asio::io_context ioc;
  boost::system::error_code ec;
  auto ws = connect_ws(ioc, std::string("/?token=") + kToken, "", ec);
  ASSERT_FALSE(ec) << ec.message();
  ws->text(true);
  ASSERT_TRUE(wait_for_first_tick(*ws));
  ws->write(
      asio::buffer(json{{"op", "setParameters"},
                        {"id", "low"},
                        {"parameters", {{{"name", "heading_pid.kp_per_deg"}, {"value", 0.03}}}}}
                       .dump()));
  EXPECT_DOUBLE_EQ(value_of(answer_with_id(*ws, "low"), "heading_pid.kp_per_deg").get<double>(),
                   0.03);
  ws->write(
      asio::buffer(json{{"op", "setParameters"},
                        {"id", "high"},
                        {"parameters", {{{"name", "heading_pid.kp_per_deg"}, {"value", 0.08}}}}}
                       .dump()));
  EXPECT_DOUBLE_EQ(value_of(answer_with_id(*ws, "high"), "heading_pid.kp_per_deg").get<double>(),
                   0.05)
      << "the answer is the value in force, not the one asked for";
}

TEST_F(LiveServerTest, EnumerationsAreNamesBothWays) {
  start_tick();
  asio::io_context ioc;
  boost::system::error_code ec;
  auto ws = connect_ws(ioc, std::string("/?token=") + kToken, "", ec);
  ASSERT_FALSE(ec) << ec.message();
  ws->text(true);
  ASSERT_TRUE(wait_for_first_tick(*ws));
  ws->write(asio::buffer(
      json{{"op", "getParameters"}, {"id", "g"}, {"parameterNames", {"avoidance.strategy"}}}
          .dump()));
  const json before = value_of(answer_with_id(*ws, "g"), "avoidance.strategy");
  ASSERT_TRUE(before.is_string()) << before.dump();
  const std::string wanted = before == "score" ? "risk_bin" : "score";
  ws->write(asio::buffer(json{{"op", "setParameters"},
                              {"id", "s"},
                              {"parameters", {{{"name", "avoidance.strategy"}, {"value", wanted}}}}}
                             .dump()));
  EXPECT_EQ(value_of(answer_with_id(*ws, "s"), "avoidance.strategy"), wanted);
  std::vector<json> statuses;
  ws->write(
      asio::buffer(json{{"op", "setParameters"},
                        {"id", "bad"},
                        {"parameters", {{{"name", "avoidance.strategy"}, {"value", "zigzag"}}}}}
                       .dump()));
  EXPECT_EQ(value_of(answer_with_id(*ws, "bad", &statuses), "avoidance.strategy"), wanted);
  ASSERT_FALSE(statuses.empty());
  const std::string message = statuses.back()["message"].get<std::string>();
  EXPECT_NE(message.find("one of selection score risk_bin"), std::string::npos) << message;
}

TEST_F(LiveServerTest, TheStatusSaysWhetherTheControlsWorkAndHowToEnableThem) {
  const json with_token = json::parse(request(http::verb::get, "/api/status").body());
  EXPECT_EQ(with_token["controls"]["enabled"], true);
  LiveOptions o = options();
  o.token.clear();
  restart(o);
  const json without = json::parse(request(http::verb::get, "/api/status").body());
  EXPECT_EQ(without["controls"]["enabled"], false);
  EXPECT_NE(without["controls"]["why"].get<std::string>().find("no token"), std::string::npos);
  EXPECT_NE(without["controls"]["how"].get<std::string>().find("live.token"), std::string::npos);
  // The page shows it (the words come from the status; the page has the place for them).
  const std::string page = request(http::verb::get, "/").body();
  EXPECT_NE(page.find("id=\"controls\""), std::string::npos);
  EXPECT_NE(page.find("Controls disabled"), std::string::npos);
}

}  // namespace
}  // namespace coxswain::live
