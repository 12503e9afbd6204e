// SPDX-License-Identifier: Apache-2.0
#include "coxswain/replay/decode_replay.hpp"

#include <array>
#include <map>
#include <memory>
#include <sstream>

#include "coxswain/drivers/arduino/codec.hpp"
#include "coxswain/drivers/myahrs/codec.hpp"
#include "coxswain/drivers/rplidar/codec.hpp"
#include "coxswain/drivers/ublox/codec.hpp"
#include "coxswain/record/layouts.hpp"
#include "coxswain/record/proto_codec.hpp"
#include "coxswain/record/recorder.hpp"

namespace coxswain::replay {
namespace {

using namespace record;  // the MCAP reader and the recorded layouts

void copy_stats(const drivers::CodecStats& s, DeviceDecodeCounts& out) {
  out.frames_ok = s.frames_ok;
  out.checksum_errors = s.checksum_errors;
  out.framing_errors = s.framing_errors;
  out.bytes_skipped = s.bytes_skipped;
}

/// The codec loop of coxswain/drivers/codec.hpp over one chunk of bytes, then the frames a
/// resync still holds.
template <class Decoder, class OnMessage>
void run_codec(Decoder& d, std::span<const std::uint8_t> bytes, OnMessage&& on_message) {
  while (!bytes.empty()) {
    const drivers::DecodeStep step = d.decode(bytes);
    bytes = bytes.subspan(step.consumed);
    if (step.produced) on_message();
  }
  while (d.decode({}).produced) on_message();
}

}  // namespace

DecodeReplayReport decode_replay(const std::filesystem::path& mcap,
                                 const DecodeReplayOptions& options) {
  DecodeReplayReport report;
  McapReader reader;
  if (!reader.open(mcap)) {
    report.error = "cannot read " + mcap.string();
    return report;
  }
  std::array<DeviceDecodeCounts, msg::kDeviceCount> counts{};
  for (std::size_t i = 0; i < counts.size(); ++i) counts[i].device = static_cast<msg::DeviceId>(i);

  drivers::rplidar::Decoder lidar;
  lidar.expect_any();  // the recording starts wherever the lidar was; accept any answer
  auto assembler = std::make_unique<drivers::rplidar::ScanAssembler>(options.lidar);
  drivers::myahrs::Decoder imu(options.imu);
  drivers::ublox::Decoder gnss;
  drivers::arduino::ArduinoCodec arduino;

  // Channel id -> what it is, filled once the channel records have been read.
  std::map<std::uint16_t, std::string> topics;
  std::map<std::uint16_t, Encoding> encodings;
  std::map<std::string, std::uint64_t> topic_counts;
  report.file = reader.read([&](const McapMessageView& m) {
    if (topics.empty()) {
      for (const auto& [id, c] : reader.channels()) {
        topics[id] = c.topic;
        Encoding e = Encoding::kProtobuf;
        if (encoding_of(c.message_encoding, e)) encodings[id] = e;
      }
    }
    const auto it = topics.find(m.channel_id);
    if (it == topics.end()) return;
    ++topic_counts[it->second];
    if (!it->second.starts_with("/raw/")) return;
    const auto encoding = encodings.find(m.channel_id);
    RawRecord raw;
    if (encoding == encodings.end() || !decode_raw(encoding->second, m.data, raw)) return;
    DeviceDecodeCounts& c = counts[static_cast<std::size_t>(raw.device)];
    ++c.raw_messages;
    if (raw.direction == drivers::RawDirection::kToDevice) {
      c.bytes_to_device += raw.bytes.size();
      return;
    }
    c.bytes_from_device += raw.bytes.size();
    switch (raw.device) {
      case msg::DeviceId::kLidar:
        run_codec(lidar, raw.bytes, [&] {
          const auto& msg = lidar.message();
          if (msg.kind != drivers::rplidar::MessageKind::kNodes) return;
          for (const auto& node : msg.nodes.span()) {
            if (assembler->add(node, raw.stamp_ns)) ++c.decoded;
          }
        });
        break;
      case msg::DeviceId::kImu:
        run_codec(imu, raw.bytes, [&] {
          if (imu.last_output() == drivers::myahrs::Output::kSample) ++c.decoded;
        });
        break;
      case msg::DeviceId::kGnss:
        run_codec(gnss, raw.bytes, [&] {
          if (gnss.message().kind == drivers::ublox::MessageKind::kFix) ++c.decoded;
        });
        break;
      case msg::DeviceId::kArduino:
        run_codec(arduino, raw.bytes, [&] {
          if (arduino.message().type == drivers::arduino::MsgType::kTelemetry) ++c.decoded;
        });
        break;
      case msg::DeviceId::kCamera:
        break;  // frames are not bytes on a serial line: nothing to re-decode
    }
  });
  copy_stats(lidar.stats().codec, counts[static_cast<std::size_t>(msg::DeviceId::kLidar)]);
  copy_stats(imu.stats().codec, counts[static_cast<std::size_t>(msg::DeviceId::kImu)]);
  copy_stats(gnss.stats(), counts[static_cast<std::size_t>(msg::DeviceId::kGnss)]);
  copy_stats(arduino.stats(), counts[static_cast<std::size_t>(msg::DeviceId::kArduino)]);

  const std::array<std::pair<msg::DeviceId, RecordChannel>, 5> decoded_channels{{
      {msg::DeviceId::kLidar, RecordChannel::kLidar},
      {msg::DeviceId::kImu, RecordChannel::kImu},
      {msg::DeviceId::kGnss, RecordChannel::kGnss},
      {msg::DeviceId::kArduino, RecordChannel::kArduino},
      {msg::DeviceId::kCamera, RecordChannel::kCamera},
  }};
  for (const auto& [device, channel] : decoded_channels) {
    const std::string topic(channel_topic(channel));
    if (reader.channel_id(topic)) {
      const auto it = topic_counts.find(topic);
      counts[static_cast<std::size_t>(device)].recorded = it == topic_counts.end() ? 0 : it->second;
    }
  }
  report.devices.assign(counts.begin(), counts.end());
  report.ok = report.file.header_ok;
  if (!report.ok) report.error = report.file.error.empty() ? "no MCAP header" : report.file.error;
  return report;
}

std::string format_decode_replay(const DecodeReplayReport& report) {
  std::ostringstream out;
  if (!report.ok) {
    out << "replay --decode: " << report.error << "\n";
    return out.str();
  }
  out << "device   raw_msgs  bytes_in  bytes_out  decoded  recorded  frames_ok  checksum_err  "
         "framing_err  skipped\n";
  for (const auto& d : report.devices) {
    out << msg::device_name(d.device);
    for (std::size_t pad = msg::device_name(d.device).size(); pad < 9; ++pad) out << ' ';
    out << d.raw_messages << "  " << d.bytes_from_device << "  " << d.bytes_to_device << "  "
        << d.decoded << "  " << (d.recorded ? std::to_string(*d.recorded) : "-") << "  "
        << d.frames_ok << "  " << d.checksum_errors << "  " << d.framing_errors << "  "
        << d.bytes_skipped << "\n";
  }
  if (report.file.truncated) out << "(file truncated: read up to the last complete chunk)\n";
  if (!report.file.error.empty()) out << "(file problem: " << report.file.error << ")\n";
  return out.str();
}

}  // namespace coxswain::replay
