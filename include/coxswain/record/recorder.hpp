// SPDX-License-Identifier: Apache-2.0
#pragma once
// The flight recorder: one MCAP file per run (src/record/FORMAT.md lists every channel).
//
// Producers never block. Each device thread owns one SPSC queue (fed through RawByteSink::on_raw),
// the tick thread owns two (record_tick, record_parameters), the log sink owns one; slots are
// fixed-size and a full queue drops the record and counts it per channel. Decoded messages are not
// pushed by anyone: a sampler thread polls the LatestStore (lock-free reads, every
// `sample_period_ns`) and queues each new value once, so disk stalls of the writer never make it
// miss one; values overwritten before it looked are counted as dropped on that channel (the raw
// bytes still hold them: `replay --decode` re-creates them).
//
// The writer thread drains the queues into McapWriter, closes a chunk (compress, write,
// fdatasync) at least every `chunk_period_ns`, logs drops at most once per `drop_log_period_ns`,
// and on a write error (disk full) stops recording, logs it once and keeps draining so the boat
// sails on. After SIGKILL or power loss the file holds every chunk closed before, i.e. all but
// about the last chunk period.
// Thread-safety: on_raw from the one thread driving each device (a device's reads and writes must
// not be teed concurrently from two threads); record_tick and record_parameters from one thread;
// stats() from any thread; start/stop from the owner.
#include <array>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <string_view>
#include <thread>
#include <utility>
#include <vector>

#include "coxswain/core/clock.hpp"
#include "coxswain/core/latest_store.hpp"
#include "coxswain/drivers/device_session.hpp"
#include "coxswain/record/layouts.hpp"
#include "coxswain/record/map_geometry.hpp"
#include "coxswain/record/tick_record.hpp"

namespace spdlog::sinks {
class sink;
}

namespace coxswain::record {

/// Every channel of a recording.
enum class RecordChannel : std::uint8_t {
  kRawLidar = 0,  // /raw/<device>, in msg::DeviceId order
  kRawImu,
  kRawGnss,
  kRawArduino,
  kRawCamera,
  kTick,         // /tick
  kGnss,         // /gnss
  kImu,          // /imu
  kLidar,        // /lidar
  kCamera,       // /camera
  kArduino,      // /arduino
  kOperator,     // /operator
  kHealth,       // /health
  kVizFix,       // /viz/fix     foxglove.LocationFix
  kVizScan,      // /viz/scan    foxglove.LaserScan
  kVizPose,      // /tf          foxglove.FrameTransform (map -> boat)
  kVizScene,     // /viz/scene   foxglove.SceneUpdate
  kLog,          // /log         foxglove.Log
  kParams,       // /params      coxswain.ParameterSet (applied live parameter sets)
  kVizMap,       // /viz/map     foxglove.SceneUpdate (mission geometry and track, "map" frame)
  kMapGeoJson,   // /map/geojson foxglove.GeoJSON (mission geometry, Map panel)
  kCameraImage,  // /camera/image        foxglove.CompressedImage (JPEG)
  kCameraAnnotations,  // /camera/annotations  foxglove.ImageAnnotations (the detections)
};
inline constexpr std::size_t kRecordChannelCount = 23;

[[nodiscard]] std::string_view channel_topic(RecordChannel channel);
[[nodiscard]] RecordChannel raw_channel(msg::DeviceId device);

/// Metadata records to write: each a name and its key/value pairs.
using MetadataRecords =
    std::vector<std::pair<std::string, std::vector<std::pair<std::string, std::string>>>>;

struct RecorderOptions {
  std::filesystem::path path;          // the .mcap file to create
  std::size_t raw_queue_slots = 1024;  // per device; each slot carries up to kRawSlotBytes
  std::size_t tick_queue_slots = 256;
  std::size_t log_queue_slots = 512;
  std::size_t params_queue_slots = 8;              // applied parameter sets (16 KiB each)
  std::size_t image_queue_slots = 4;               // camera images (kMaxImageBytes each)
  core::TimeNs chunk_period_ns = core::kNsPerSec;  // a crash loses at most about this much
  std::size_t chunk_size_bytes = 4U << 20U;
  int zstd_level = 3;
  bool sync = true;  // fdatasync every closed chunk
  // Each wake of the two threads costs a few microseconds of a core (a context switch, more in
  // a VM) whatever it finds, so they wake no more often than the data needs: the writer's queues
  // hold seconds, and the fastest stream the store takes (100 Hz) is 10 ms apart.
  core::TimeNs idle_sleep_ns = 10 * core::kNsPerMs;  // writer thread nap when all queues are empty
  core::TimeNs sample_period_ns = 2 * core::kNsPerMs;  // store sampler poll period
  // false: no sampler thread; the owner calls sample() after every store update instead (the
  // simulator, whose virtual time outruns any polling thread, so no value is ever overwritten).
  bool sampler_thread = true;
  std::size_t sample_queue_slots = 1024;  // decoded messages waiting for the writer
  // Scans waiting for the writer (53 KiB each): 3 s at 10 Hz, so a writer held up by a slow
  // fdatasync loses none (a missing scan makes a tick unreplayable).
  std::size_t lidar_queue_slots = 32;
  core::TimeNs drop_log_period_ns = 5 * core::kNsPerSec;
  std::size_t scan_viz_bins = 720;  // foxglove.LaserScan resolution
  // /viz/scene, /tf and /viz/scan at most this often (0: every tick and scan). They are for
  // viewing: every tick is in /tick and every scan in /lidar for replay and the report, and a
  // scene per 50 Hz tick was most of the recorder's time and bytes.
  core::TimeNs viz_period_ns = 200 * core::kNsPerMs;
  /// The mission's geometry for /viz/map and /map/geojson, written with the track at the first
  /// tick and every `map_period_ns` after (a viewer seeking into the file finds the last one).
  MapGeometry map;
  core::TimeNs map_period_ns = 5 * core::kNsPerSec;
  double track_spacing_m = 1.0;  // the track's first spacing (record::TrackLine)
  std::string config_yaml;       // effective configuration (Metadata "config")
  std::string build_version;     // Metadata "build"
  /// Further Metadata records (name -> key/value), e.g. the simulator's "course".
  MetadataRecords extra_metadata;
};

struct RecorderChannelStats {
  std::uint64_t written = 0;  // messages handed to the MCAP writer
  std::uint64_t dropped = 0;  // queue full, slot overwritten before sampling, or after failure
};

/// A consistent-enough copy of the counters (each counter is exact; they are read one by one).
struct RecorderStats {
  std::array<RecorderChannelStats, kRecordChannelCount> channels{};
  std::uint64_t raw_bytes = 0;  // device bytes recorded in /raw/*
  std::uint64_t file_bytes = 0;
  std::uint64_t chunks = 0;
  bool running = false;  // writer thread alive and recording
  bool failed = false;   // recording stopped on an error (the run goes on)
  std::string error;

  [[nodiscard]] const RecorderChannelStats& operator[](RecordChannel c) const {
    return channels[static_cast<std::size_t>(c)];
  }
  [[nodiscard]] std::uint64_t total_dropped() const;
};

class Recorder final : public drivers::RawByteSink {
 public:
  /// Bytes of one raw queue slot; a longer on_raw() is split over several slots/messages.
  static constexpr std::size_t kRawSlotBytes = 1024;

  /// `store` (may be null) is sampled for the decoded channels; `clock` stamps log lines and
  /// paces chunk closes. Both must outlive the recorder.
  Recorder(RecorderOptions options, const core::LatestStore* store, const core::Clock& clock);
  ~Recorder() override;
  Recorder(const Recorder&) = delete;
  Recorder& operator=(const Recorder&) = delete;

  /// Creates the file, writes schemas, channels and metadata, starts the writer thread. False
  /// (with stats().error) when the file cannot be created; the recorder then drops everything.
  bool start();
  /// Drains the queues, samples the store once more, finishes the file and joins the thread.
  /// `closing_metadata` is written after the last message (what is known only at the end, such
  /// as the simulator judge's score).
  void stop(MetadataRecords closing_metadata = {});

  void on_raw(msg::DeviceId device, drivers::RawDirection direction, core::TimeNs stamp_ns,
              std::span<const std::uint8_t> bytes) noexcept override;
  /// Copies one tick into the tick queue (bounded work, no allocation). False when dropped.
  bool record_tick(const TickInput& tick) noexcept;
  /// Queues a parameter set applied between two steps for /params: `tick_index` is the first
  /// tick stepped with it (replay applies it before stepping that tick). Same thread as
  /// record_tick. Bounded work, no allocation. False when dropped (queue full, or the set does
  /// not fit kMaxParameterBytes).
  bool record_parameters(std::uint64_t tick_index, core::TimeNs stamp_ns,
                         std::span<const NamedValue> values) noexcept;
  /// Bytes of the largest camera image recorded (a 640 px JPEG of a photo is tens of KiB).
  static constexpr std::size_t kMaxImageBytes = std::size_t{512} << 10U;
  /// Queues a JPEG frame for /camera/image and its detections for /camera/annotations (`scale`:
  /// the image's width over the detector's, to place them). One producer thread. Bounded work
  /// (one copy), no allocation. False when dropped (queue full, or larger than kMaxImageBytes).
  bool record_image(core::TimeNs stamp_ns, std::span<const std::uint8_t> jpeg,
                    const msg::CameraDetections& detections, double scale) noexcept;
  /// Queues a log line for /log. One producer at a time (log_sink() serializes its callers).
  bool record_log(core::TimeNs stamp_ns, int spdlog_level, std::string_view logger,
                  std::string_view text) noexcept;
  /// An spdlog sink feeding /log; add it to the loggers whose lines belong in the recording.
  [[nodiscard]] std::shared_ptr<spdlog::sinks::sink> log_sink();

  /// With `sampler_thread = false` only: takes every new store value now, on the caller's
  /// thread (always the same one). Never blocks; a full queue drops and counts as usual.
  void sample() noexcept;
  /// How many sample() passes the decoded-message queues have room for even if every store slot
  /// changed (0 = a pass now could drop), so a caller of sample() can wait for the writer.
  [[nodiscard]] std::size_t queue_room() const;

  [[nodiscard]] RecorderStats stats() const;

 private:
  struct RawSlot;
  struct TickSlot;
  struct LogSlot;
  struct ParamsSlot;
  struct ImageSlot;
  struct Queues;
  struct WriterState;
  struct SamplerState;

  void run();
  void run_sampler();
  bool drain_once();
  bool sample_store();
  void write(RecordChannel channel, core::TimeNs stamp_ns, std::span<const std::uint8_t> data);
  void write(RecordChannel channel, core::TimeNs stamp_ns, std::string_view json);
  void note_failure();
  void log_drops(bool force);
  void count_drop(RecordChannel c, std::uint64_t n = 1) noexcept {
    dropped_[static_cast<std::size_t>(c)].fetch_add(n, std::memory_order_relaxed);
  }

  RecorderOptions options_;
  const core::LatestStore* store_;
  const core::Clock& clock_;
  std::shared_ptr<Queues> queues_;
  std::unique_ptr<WriterState> state_;
  std::unique_ptr<SamplerState> sampler_;
  std::thread thread_;
  std::thread sampler_thread_;
  std::atomic<bool> sampler_stop_{false};
  std::atomic<bool> accepting_{false};
  std::atomic<bool> stop_{false};
  std::mutex stop_mutex_;  // wakes the napping writer thread on stop(); producers never touch it
  MetadataRecords closing_metadata_;  // set by stop() before the stop flag, read by the writer
  std::condition_variable stop_cv_;
  std::atomic<bool> running_{false};
  std::atomic<bool> failed_{false};
  mutable std::mutex error_mutex_;  // guards error_ only (never taken by a producer)
  std::string error_;
  std::array<std::atomic<std::uint64_t>, kRecordChannelCount> written_{};
  std::array<std::atomic<std::uint64_t>, kRecordChannelCount> dropped_{};
  std::atomic<std::uint64_t> raw_bytes_{0};
  std::atomic<std::uint64_t> file_bytes_{0};
  std::atomic<std::uint64_t> chunks_{0};
};

}  // namespace coxswain::record
