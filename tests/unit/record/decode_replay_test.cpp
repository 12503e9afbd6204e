// SPDX-License-Identifier: Apache-2.0
// replay --decode: the codecs re-run on recorded raw bytes find every frame the streams hold,
// however the transport split them, and count corrupted ones as errors.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "coxswain/record/recorder.hpp"
#include "coxswain/replay/decode_replay.hpp"
#include "device_streams.hpp"

namespace coxswain::record {
using replay::decode_replay;
using replay::DecodeReplayReport;
using replay::format_decode_replay;
namespace {

namespace fs = std::filesystem;

/// Tees `bytes` to the recorder in reads of `piece` bytes, as a transport would.
void tee(Recorder& rec, msg::DeviceId device, const std::vector<std::uint8_t>& bytes,
         std::size_t piece) {
  for (std::size_t at = 0; at < bytes.size(); at += piece) {
    const std::size_t n = std::min(piece, bytes.size() - at);
    rec.on_raw(device, drivers::RawDirection::kFromDevice, static_cast<core::TimeNs>(at),
               std::span<const std::uint8_t>(bytes).subspan(at, n));
  }
}

TEST(DecodeReplay, CodecsRecoverEveryFrameFromRecordedRawBytes) {
  const fs::path path =
      fs::temp_directory_path() / ("coxswain_replay_" + std::to_string(::getpid()) + ".mcap");
  core::SteadyClock clock;
  RecorderOptions o;
  o.path = path;
  o.sync = false;
  o.raw_queue_slots = 1 << 14;  // no drops: the counts below are exact
  const auto imu = test::imu_stream(120);
  {
    Recorder rec(o, nullptr, clock);
    ASSERT_TRUE(rec.start());
    tee(rec, msg::DeviceId::kLidar, test::lidar_stream(6, 400), 333);
    tee(rec, msg::DeviceId::kGnss, test::gnss_stream(40), 17);
    tee(rec, msg::DeviceId::kImu, imu, 64);
    auto ard = test::arduino_stream(50);
    ard[10] ^= 0xFF;  // corrupt the first frame: one CRC/framing error, 49 good frames
    tee(rec, msg::DeviceId::kArduino, ard, 5);
    const std::vector<std::uint8_t> cmd{1, 2, 3};
    rec.on_raw(msg::DeviceId::kArduino, drivers::RawDirection::kToDevice, 0, cmd);
    rec.stop();
    ASSERT_EQ(rec.stats().total_dropped(), 0U);
  }
  const DecodeReplayReport r = decode_replay(path);
  ASSERT_TRUE(r.ok) << r.error;
  ASSERT_EQ(r.devices.size(), msg::kDeviceCount);
  const auto& lidar = r.devices[static_cast<std::size_t>(msg::DeviceId::kLidar)];
  EXPECT_EQ(lidar.frames_ok, 6U * 400U);
  EXPECT_EQ(lidar.decoded, 5U);  // seam astern: the first half revolution is dropped
  EXPECT_EQ(lidar.checksum_errors + lidar.framing_errors, 0U);
  const auto& gnss = r.devices[static_cast<std::size_t>(msg::DeviceId::kGnss)];
  EXPECT_EQ(gnss.decoded, 40U);
  EXPECT_EQ(gnss.checksum_errors, 0U);
  const auto& imu_counts = r.devices[static_cast<std::size_t>(msg::DeviceId::kImu)];
  EXPECT_EQ(imu_counts.decoded, 120U);
  EXPECT_EQ(imu_counts.bytes_from_device, imu.size());
  const auto& ard_counts = r.devices[static_cast<std::size_t>(msg::DeviceId::kArduino)];
  EXPECT_EQ(ard_counts.decoded, 49U);
  EXPECT_GE(ard_counts.checksum_errors + ard_counts.framing_errors, 1U);
  EXPECT_EQ(ard_counts.bytes_to_device, 3U);
  // The recording has the decoded channels (empty here: no store was attached).
  ASSERT_TRUE(lidar.recorded.has_value());
  EXPECT_EQ(*lidar.recorded, 0U);
  const std::string table = format_decode_replay(r);
  EXPECT_NE(table.find("gnss"), std::string::npos);
  EXPECT_NE(table.find("arduino"), std::string::npos);
  fs::remove(path);
}

TEST(DecodeReplay, MissingFileIsAnErrorNotACrash) {
  const DecodeReplayReport r = decode_replay("/nonexistent/run.mcap");
  EXPECT_FALSE(r.ok);
  EXPECT_NE(format_decode_replay(r).find("cannot read"), std::string::npos);
}

}  // namespace
}  // namespace coxswain::record
