// SPDX-License-Identifier: Apache-2.0
#include "coxswain/app/decode_capture.hpp"

#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <ostream>
#include <string>
#include <vector>

#include "coxswain/drivers/arduino/codec.hpp"
#include "coxswain/drivers/myahrs/codec.hpp"
#include "coxswain/drivers/rplidar/codec.hpp"
#include "coxswain/drivers/ublox/codec.hpp"

namespace coxswain::app {
namespace {

using nlohmann::json;

json codec_stats_json(const drivers::CodecStats& s) {
  return {{"bytes_in", s.bytes_in},
          {"frames_ok", s.frames_ok},
          {"messages_out", s.messages_out},
          {"checksum_errors", s.checksum_errors},
          {"framing_errors", s.framing_errors},
          {"bytes_skipped", s.bytes_skipped},
          {"unsupported", s.unsupported}};
}

std::string hex_byte(unsigned v) {
  std::array<char, 8> buf{};
  std::snprintf(buf.data(), buf.size(), "0x%02X", v & 0xFFU);
  return buf.data();
}

// --- u-blox -----------------------------------------------------------------------------------

const char* fix_type_name(msg::FixType t) {
  switch (t) {
    case msg::FixType::kNoFix:
      return "no_fix";
    case msg::FixType::kDeadReckoning:
      return "dead_reckoning";
    case msg::FixType::k2D:
      return "2d";
    case msg::FixType::k3D:
      return "3d";
    case msg::FixType::kGnssDeadReckoning:
      return "gnss_dead_reckoning";
    case msg::FixType::kTimeOnly:
      return "time_only";
  }
  return "unknown";
}

const char* rtk_name(msg::RtkSolution r) {
  switch (r) {
    case msg::RtkSolution::kNone:
      return "none";
    case msg::RtkSolution::kFloat:
      return "float";
    case msg::RtkSolution::kFixed:
      return "fixed";
  }
  return "unknown";
}

const char* gnss_source_name(msg::GnssSource s) {
  switch (s) {
    case msg::GnssSource::kUbxNavPvt:
      return "ubx_nav_pvt";
    case msg::GnssSource::kNmeaGga:
      return "nmea_gga";
    case msg::GnssSource::kNmeaRmc:
      return "nmea_rmc";
    case msg::GnssSource::kNmeaGll:
      return "nmea_gll";
    case msg::GnssSource::kUbxNavLegacy:
      return "ubx_nav_legacy";
  }
  return "unknown";
}

json ublox_json(const drivers::ublox::Message& m) {
  using drivers::ublox::MessageKind;
  switch (m.kind) {
    case MessageKind::kFix: {
      const msg::GnssFix& f = m.fix;
      return {{"type", "fix"},
              {"source", gnss_source_name(f.source)},
              {"nmea_address", std::string(m.nmea_address)},
              {"fix_type", fix_type_name(f.fix_type)},
              {"fix_ok", f.fix_ok},
              {"diff_soln", f.diff_soln},
              {"rtk", rtk_name(f.rtk)},
              {"lat_deg", f.lat_deg},
              {"lon_deg", f.lon_deg},
              {"height_msl_m", f.height_msl_m},
              {"h_acc_m", f.h_acc_m},
              {"v_acc_m", f.v_acc_m},
              {"hdop", f.hdop},
              {"satellites", f.satellites},
              {"velocity_valid", f.velocity_valid},
              {"vel_north_mps", f.vel_north_mps},
              {"vel_east_mps", f.vel_east_mps},
              {"vel_down_mps", f.vel_down_mps},
              {"ground_speed_mps", f.ground_speed_mps},
              {"course_deg", f.course_deg},
              {"utc_ns", f.utc_ns},
              {"itow_ms", f.itow_ms}};
    }
    case MessageKind::kHpPosLlh:
      return {{"type", "hpposllh"},
              {"itow_ms", m.hp.itow_ms},
              {"invalid_llh", m.hp.invalid_llh},
              {"lat_deg", m.hp.lat_deg},
              {"lon_deg", m.hp.lon_deg},
              {"height_m", m.hp.height_m},
              {"height_msl_m", m.hp.height_msl_m},
              {"h_acc_m", m.hp.h_acc_m},
              {"v_acc_m", m.hp.v_acc_m}};
    case MessageKind::kAck:
    case MessageKind::kNak:
      return {{"type", m.kind == MessageKind::kAck ? "ack" : "nak"},
              {"class", hex_byte(m.ubx.msg_class)},
              {"id", hex_byte(m.ubx.msg_id)}};
    case MessageKind::kRtcm3:
      return {{"type", "rtcm3"},
              {"message_type", m.rtcm3.message_type},
              {"length_bytes", m.rtcm3.bytes.size()}};
    case MessageKind::kOtherUbx:
      return {
          {"type", "ubx"}, {"class", hex_byte(m.ubx.msg_class)}, {"id", hex_byte(m.ubx.msg_id)}};
    case MessageKind::kOtherNmea:
      return {{"type", "nmea"}, {"address", std::string(m.nmea_address)}};
    case MessageKind::kNone:
      break;
  }
  return {{"type", "none"}};
}

// --- myAHRS+ ----------------------------------------------------------------------------------

json myahrs_json(const drivers::myahrs::Decoder& d) {
  using drivers::myahrs::Output;
  if (d.last_output() == Output::kResponse) {
    const auto& r = d.response();
    json attributes = json::object();
    for (const auto& a : r.attributes) attributes[std::string(a.name)] = std::string(a.value);
    json arguments = json::array();
    for (const auto& a : r.arguments) arguments.push_back(std::string(a));
    return {{"type", "response"},
            {"command", std::string(r.command)},
            {"ok", r.ok},
            {"attributes", attributes},
            {"arguments", arguments}};
  }
  const msg::ImuSample& s = d.sample();
  const drivers::myahrs::SampleDetail& det = d.sample_detail();
  json j = {{"type", "sample"},
            {"encoding", det.encoding == drivers::myahrs::Encoding::kAscii ? "ascii" : "binary"},
            {"sequence", s.sequence}};
  if (det.has_attitude) {
    j["roll_deg"] = s.roll_deg;
    j["pitch_deg"] = s.pitch_deg;
    j["yaw_magnetic_deg"] = s.yaw_magnetic_deg;
    j["heading_deg"] = s.heading_deg;
    j["from_quaternion"] = det.from_quaternion;
  }
  if (det.has_quaternion) j["quaternion_xyzw"] = det.quaternion_xyzw;
  if (s.has_inertial) {
    j["accel_g"] = s.accel_g;
    j["gyro_dps"] = s.gyro_dps;
    j["mag_ut"] = s.mag_ut;
    j["temperature_c"] = s.temperature_c;
  }
  if (det.has_raw) j["raw_imu_lsb"] = det.raw_imu;
  return j;
}

json myahrs_stats_json(const drivers::myahrs::DecoderStats& s) {
  json j = codec_stats_json(s.codec);
  j["ascii_lines_ok"] = s.ascii_lines_ok;
  j["binary_frames_ok"] = s.binary_frames_ok;
  j["ascii_checksum_errors"] = s.ascii_checksum_errors;
  j["binary_checksum_errors"] = s.binary_checksum_errors;
  j["ascii_bad_checksum_field"] = s.ascii_bad_checksum_field;
  j["ascii_overlong"] = s.ascii_overlong;
  j["ascii_bad_byte"] = s.ascii_bad_byte;
  j["ascii_interrupted"] = s.ascii_interrupted;
  j["ascii_bad_fields"] = s.ascii_bad_fields;
  j["binary_overlong"] = s.binary_overlong;
  j["binary_aborted"] = s.binary_aborted;
  j["binary_malformed"] = s.binary_malformed;
  j["unknown_sentences"] = s.unknown_sentences;
  j["binary_without_data"] = s.binary_without_data;
  j["requests_seen"] = s.requests_seen;
  j["error_responses"] = s.error_responses;
  return j;
}

// --- RPLIDAR ----------------------------------------------------------------------------------

json rplidar_json(const drivers::rplidar::Message& m) {
  using drivers::rplidar::MessageKind;
  switch (m.kind) {
    case MessageKind::kDeviceInfo: {
      std::string serial;
      for (const auto b : m.device_info.serial) serial += hex_byte(b).substr(2);
      const auto model = drivers::rplidar::model_info(m.device_info);
      return {{"type", "device_info"},
              {"model", m.device_info.model},
              {"model_name", std::string(model.name_view())},
              {"firmware_major", m.device_info.firmware_major},
              {"firmware_minor", m.device_info.firmware_minor},
              {"hardware", m.device_info.hardware},
              {"serial", serial}};
    }
    case MessageKind::kHealth:
      return {{"type", "health"}, {"status", m.health.status}, {"error_code", m.health.error_code}};
    case MessageKind::kSampleRate:
      return {{"type", "sample_rate"},
              {"standard_us", m.sample_rate.standard_us},
              {"express_us", m.sample_rate.express_us}};
    case MessageKind::kLidarConf:
      return {{"type", "lidar_conf"},
              {"conf_type", hex_byte(m.lidar_conf.type)},
              {"conf_type_value", m.lidar_conf.type},
              {"size_bytes", m.lidar_conf.size},
              {"as_uint", m.lidar_conf.as_uint(std::min<std::size_t>(4, m.lidar_conf.size))}};
    case MessageKind::kAccBoardFlag:
      return {{"type", "acc_board_flag"},
              {"flag", m.acc_board.flag},
              {"pwm_supported", m.acc_board.pwm_supported()}};
    case MessageKind::kNodes: {
      json nodes = json::array();
      for (const auto& n : m.nodes.span()) {
        nodes.push_back({{"angle_deg", n.angle_deg()},
                         {"distance_mm", n.distance_mm()},
                         {"quality", n.quality},
                         {"start_of_scan", n.start_of_scan()}});
      }
      return {{"type", "nodes"},
              {"answer_type", hex_byte(static_cast<unsigned>(m.nodes.source))},
              {"count", m.nodes.count},
              {"nodes", nodes}};
    }
    case MessageKind::kNone:
      break;
  }
  return {{"type", "none"}};
}

json rplidar_stats_json(const drivers::rplidar::DecoderStats& s) {
  json j = codec_stats_json(s.codec);
  j["descriptors"] = s.descriptors;
  j["unexpected_answers"] = s.unexpected_answers;
  j["node_check_errors"] = s.node_check_errors;
  j["capsule_sync_errors"] = s.capsule_sync_errors;
  j["capsule_restarts"] = s.capsule_restarts;
  j["dense_rejected"] = s.dense_rejected;
  j["nodes_out"] = s.nodes_out;
  return j;
}

// --- Arduino ----------------------------------------------------------------------------------

json arduino_json(const drivers::arduino::BoardMessage& m) {
  using drivers::arduino::MsgType;
  switch (m.type) {
    case MsgType::kReady:
      return {
          {"type", "ready"},
          {"seq", m.seq},
          {"protocol_version", m.ready.protocol_version},
          {"firmware", std::to_string(m.ready.fw_major) + "." + std::to_string(m.ready.fw_minor) +
                           "." + std::to_string(m.ready.fw_patch)},
          {"failsafe_ms", m.ready.failsafe_ms},
          {"neutral_us", m.ready.neutral_us},
          {"reset_cause", m.ready.reset_cause},
          {"rc_channels", m.ready.rc_channels}};
    case MsgType::kPong:
      return {{"type", "pong"},
              {"seq", m.seq},
              {"token", m.pong.token},
              {"uptime_ms", m.pong.uptime_ms}};
    case MsgType::kTelemetry: {
      const auto& t = m.telemetry;
      return {{"type", "telemetry"},
              {"seq", m.seq},
              {"uptime_ms", t.uptime_ms},
              {"applied_pulse_us", t.applied_pulse_us},
              {"rc_pulse_us", t.rc_pulse_us},
              {"led", t.led},
              {"mode", t.mode},
              {"flags", t.flags},
              {"source", t.source},
              {"supply_mv", t.supply_mv},
              {"last_seq", t.last_seq},
              {"rx_frames_ok", t.rx_frames_ok},
              {"rx_crc_errors", t.rx_crc_errors},
              {"rx_framing_errors", t.rx_framing_errors},
              {"rx_bytes_skipped", t.rx_bytes_skipped},
              {"seq_gaps", t.seq_gaps},
              {"seq_duplicates", t.seq_duplicates},
              {"failsafe_events", t.failsafe_events}};
    }
    case MsgType::kHello:
    case MsgType::kPing:
    case MsgType::kSetOutputs:
      break;
  }
  return {{"type", "other"}, {"msg_type", hex_byte(static_cast<unsigned>(m.type))}};
}

}  // namespace

std::optional<CaptureFormat> parse_capture_format(std::string_view name) {
  if (name == "rplidar") return CaptureFormat::kRplidar;
  if (name == "myahrs") return CaptureFormat::kMyahrs;
  if (name == "ublox") return CaptureFormat::kUblox;
  if (name == "arduino") return CaptureFormat::kArduino;
  return std::nullopt;
}

std::string_view capture_format_name(CaptureFormat format) {
  switch (format) {
    case CaptureFormat::kRplidar:
      return "rplidar";
    case CaptureFormat::kMyahrs:
      return "myahrs";
    case CaptureFormat::kUblox:
      return "ublox";
    case CaptureFormat::kArduino:
      return "arduino";
  }
  return "unknown";
}

struct CaptureDecoder::Impl {
  explicit Impl(CaptureFormat f) : format(f) { rplidar.expect_any(); }

  // One decode step of the chosen codec; emits what it produced.
  drivers::DecodeStep step(std::span<const std::uint8_t> input, std::uint64_t end_offset,
                           const Emit& emit) {
    drivers::DecodeStep s;
    json j;
    switch (format) {
      case CaptureFormat::kRplidar:
        s = rplidar.decode(input);
        if (s.produced) j = rplidar_json(rplidar.message());
        break;
      case CaptureFormat::kMyahrs:
        s = myahrs.decode(input);
        if (s.produced) j = myahrs_json(myahrs);
        break;
      case CaptureFormat::kUblox:
        s = ublox.decode(input);
        if (s.produced) j = ublox_json(ublox.message());
        break;
      case CaptureFormat::kArduino:
        s = arduino.decode(input);
        if (s.produced) j = arduino_json(arduino.message());
        break;
    }
    if (s.produced) {
      ++messages;
      j["end_offset_bytes"] = end_offset + s.consumed;
      emit(j);
    }
    return s;
  }

  CaptureFormat format;
  std::uint64_t bytes_fed = 0;
  std::uint64_t messages = 0;
  drivers::rplidar::Decoder rplidar;
  drivers::myahrs::Decoder myahrs;
  drivers::ublox::Decoder ublox;
  drivers::arduino::ArduinoCodec arduino;
};

CaptureDecoder::CaptureDecoder(CaptureFormat format) : impl_(std::make_unique<Impl>(format)) {}
CaptureDecoder::~CaptureDecoder() = default;

void CaptureDecoder::feed(std::span<const std::uint8_t> bytes, const Emit& emit) {
  while (!bytes.empty()) {
    const drivers::DecodeStep s = impl_->step(bytes, impl_->bytes_fed, emit);
    if (s.consumed == 0) break;  // codec convention: cannot happen for non-empty input
    bytes = bytes.subspan(s.consumed);
    impl_->bytes_fed += s.consumed;
  }
}

void CaptureDecoder::finish(const Emit& emit) {
  // Only these two codecs hold complete frames back after a resync (see their headers).
  if (impl_->format != CaptureFormat::kUblox && impl_->format != CaptureFormat::kArduino) return;
  while (impl_->step({}, impl_->bytes_fed, emit).produced) {
  }
}

nlohmann::json CaptureDecoder::summary() const {
  json counters;
  switch (impl_->format) {
    case CaptureFormat::kRplidar:
      counters = rplidar_stats_json(impl_->rplidar.stats());
      break;
    case CaptureFormat::kMyahrs:
      counters = myahrs_stats_json(impl_->myahrs.stats());
      break;
    case CaptureFormat::kUblox:
      counters = codec_stats_json(impl_->ublox.stats());
      break;
    case CaptureFormat::kArduino:
      counters = codec_stats_json(impl_->arduino.stats());
      break;
  }
  return {{"summary", true},
          {"device", capture_format_name(impl_->format)},
          {"bytes", impl_->bytes_fed},
          {"messages", impl_->messages},
          {"codec", counters}};
}

int decode_capture_file(CaptureFormat format, const std::filesystem::path& path, std::ostream& out,
                        std::ostream& err) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    err << path.string() << ": cannot open: " << std::strerror(errno) << "\n";
    return 1;
  }
  CaptureDecoder decoder(format);
  const CaptureDecoder::Emit emit = [&out](const json& j) { out << j.dump() << "\n"; };
  std::vector<char> buf(std::size_t{64} * 1024);
  while (in) {
    in.read(buf.data(), static_cast<std::streamsize>(buf.size()));
    const auto n = static_cast<std::size_t>(in.gcount());
    if (n == 0) break;
    decoder.feed({reinterpret_cast<const std::uint8_t*>(buf.data()), n}, emit);
  }
  if (in.bad()) {
    err << path.string() << ": read error\n";
    return 1;
  }
  decoder.finish(emit);
  out << decoder.summary().dump() << "\n";
  return 0;
}

}  // namespace coxswain::app
