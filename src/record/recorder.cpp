// SPDX-License-Identifier: Apache-2.0
#include "coxswain/record/recorder.hpp"

#include <pthread.h>
#include <spdlog/sinks/base_sink.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <ctime>
#include <vector>

#include "coxswain/record/foxglove.hpp"
#include "coxswain/record/layouts.hpp"
#include "coxswain/record/mcap_writer.hpp"
#include "coxswain/record/proto_codec.hpp"
#include "coxswain/record/spsc_ring.hpp"
#include "coxswain/record/track_line.hpp"

namespace coxswain::record {

std::string_view channel_topic(RecordChannel channel) {
  switch (channel) {
    case RecordChannel::kRawLidar:
      return "/raw/lidar";
    case RecordChannel::kRawImu:
      return "/raw/imu";
    case RecordChannel::kRawGnss:
      return "/raw/gnss";
    case RecordChannel::kRawArduino:
      return "/raw/arduino";
    case RecordChannel::kRawCamera:
      return "/raw/camera";
    case RecordChannel::kTick:
      return "/tick";
    case RecordChannel::kGnss:
      return "/gnss";
    case RecordChannel::kImu:
      return "/imu";
    case RecordChannel::kLidar:
      return "/lidar";
    case RecordChannel::kCamera:
      return "/camera";
    case RecordChannel::kArduino:
      return "/arduino";
    case RecordChannel::kOperator:
      return "/operator";
    case RecordChannel::kHealth:
      return "/health";
    case RecordChannel::kVizFix:
      return "/viz/fix";
    case RecordChannel::kVizScan:
      return "/viz/scan";
    case RecordChannel::kVizPose:
      return "/tf";
    case RecordChannel::kVizScene:
      return "/viz/scene";
    case RecordChannel::kLog:
      return "/log";
    case RecordChannel::kParams:
      return "/params";
    case RecordChannel::kVizMap:
      return "/viz/map";
    case RecordChannel::kMapGeoJson:
      return "/map/geojson";
    case RecordChannel::kCameraImage:
      return "/camera/image";
    case RecordChannel::kCameraAnnotations:
      return "/camera/annotations";
  }
  return "/unknown";
}

RecordChannel raw_channel(msg::DeviceId device) {
  return static_cast<RecordChannel>(static_cast<std::uint8_t>(RecordChannel::kRawLidar) +
                                    static_cast<std::uint8_t>(device));
}

std::uint64_t RecorderStats::total_dropped() const {
  std::uint64_t n = 0;
  for (const auto& c : channels) n += c.dropped;
  return n;
}

struct Recorder::RawSlot {
  core::TimeNs stamp_ns = 0;
  drivers::RawDirection direction = drivers::RawDirection::kFromDevice;
  std::uint16_t length = 0;
  std::array<std::uint8_t, kRawSlotBytes> bytes{};
};

struct Recorder::TickSlot {
  core::TimeNs now_ns = 0;
  std::uint16_t length = 0;
  std::array<std::uint8_t, proto::kMaxTickBytes> bytes{};
  std::uint16_t state_path_length = 0;
  std::array<char, kMaxStatePathBytes> state_path{};
  bool has_viz = false;
  TickViz viz;
};

struct Recorder::LogSlot {
  static constexpr std::size_t kMaxText = 480;
  static constexpr std::size_t kMaxName = 31;
  core::TimeNs stamp_ns = 0;
  int level = 0;
  std::uint8_t name_length = 0;
  std::array<char, kMaxName> name{};
  std::uint16_t text_length = 0;
  std::array<char, kMaxText> text{};
};

struct Recorder::ParamsSlot {
  core::TimeNs stamp_ns = 0;
  std::uint32_t length = 0;
  std::array<std::uint8_t, proto::kMaxParameterBytes> bytes{};
};

struct Recorder::ImageSlot {
  core::TimeNs stamp_ns = 0;
  std::uint32_t length = 0;
  double scale = 1.0;
  msg::CameraDetections detections{};
  std::unique_ptr<std::uint8_t[]> bytes = std::make_unique<std::uint8_t[]>(kMaxImageBytes);
};

/// A decoded message sampled from the store, already encoded for its channel.
struct SampleSlot {
  RecordChannel channel = RecordChannel::kGnss;
  core::TimeNs stamp_ns = 0;
  std::uint32_t length = 0;
  std::array<std::uint8_t, 1024> bytes{};  // the largest, a full CameraDetections, is ~700
};
struct LidarSampleSlot {
  core::TimeNs stamp_ns = 0;
  std::uint32_t length = 0;
  std::array<std::uint8_t, proto::kMaxLidarBytes> bytes{};
};

struct Recorder::Queues {
  explicit Queues(const RecorderOptions& o)
      : raw{SpscRing<RawSlot>(o.raw_queue_slots), SpscRing<RawSlot>(o.raw_queue_slots),
            SpscRing<RawSlot>(o.raw_queue_slots), SpscRing<RawSlot>(o.raw_queue_slots),
            SpscRing<RawSlot>(o.raw_queue_slots)},
        tick(o.tick_queue_slots),
        log(o.log_queue_slots),
        params(o.params_queue_slots),
        images(o.image_queue_slots),
        samples(o.sample_queue_slots),
        lidar_samples(o.lidar_queue_slots) {}
  std::array<SpscRing<RawSlot>, msg::kDeviceCount> raw;
  SpscRing<TickSlot> tick;
  SpscRing<LogSlot> log;
  SpscRing<ParamsSlot> params;   // producer: the tick thread
  SpscRing<ImageSlot> images;    // producer: the camera image thread
  SpscRing<SampleSlot> samples;  // producer: the sampler thread
  SpscRing<LidarSampleSlot> lidar_samples;
  std::atomic<bool> log_accepting{false};
  std::atomic<std::uint64_t> log_dropped{0};
  std::atomic<core::TimeNs> now_ns{0};  // the recorder clock as last read by the writer thread

  bool push_log(core::TimeNs stamp_ns, int level, std::string_view logger,
                std::string_view text) noexcept {
    if (!log_accepting.load(std::memory_order_acquire)) {
      log_dropped.fetch_add(1, std::memory_order_relaxed);
      return false;
    }
    LogSlot* s = log.try_claim();
    if (s == nullptr) {
      log_dropped.fetch_add(1, std::memory_order_relaxed);
      return false;
    }
    s->stamp_ns = stamp_ns;
    s->level = level;
    s->name_length = static_cast<std::uint8_t>(std::min(logger.size(), LogSlot::kMaxName));
    if (s->name_length > 0) std::memcpy(s->name.data(), logger.data(), s->name_length);
    s->text_length = static_cast<std::uint16_t>(std::min(text.size(), LogSlot::kMaxText));
    if (s->text_length > 0) std::memcpy(s->text.data(), text.data(), s->text_length);
    log.publish();
    return true;
  }
};

/// Everything only the writer thread touches.
/// A rate limit on a stream of stamps: due at the first, then once per period on a fixed
/// schedule (from the last due time, not the last stamp), so jitter in the stamps never skips
/// one; a stream that fell a period behind starts the schedule again from its stamp.
struct VizSchedule {
  bool started = false;
  core::TimeNs next_ns = 0;
  bool due(core::TimeNs stamp_ns, core::TimeNs period_ns) {
    if (period_ns <= 0) return true;
    if (started && stamp_ns < next_ns) return false;
    next_ns =
        started && stamp_ns - next_ns < period_ns ? next_ns + period_ns : stamp_ns + period_ns;
    started = true;
    return true;
  }
};

struct Recorder::WriterState {
  explicit WriterState(const RecorderOptions& o)
      : writer(McapWriterOptions{.profile = "coxswain",
                                 .library = "coxswain " + o.build_version,
                                 .chunk_size_bytes = o.chunk_size_bytes,
                                 .compress = true,
                                 .zstd_level = o.zstd_level,
                                 .sync = o.sync,
                                 .buffer_bytes = 1U << 20U}),
        scratch(Recorder::kRawSlotBytes + proto::kMaxRawOverheadBytes),
        lidar(std::make_unique<core::Sample<msg::LidarScan>>()),
        track(o.track_spacing_m) {}
  McapWriter writer;
  std::array<std::uint16_t, kRecordChannelCount> channel_ids{};
  std::vector<std::uint8_t> scratch;
  std::unique_ptr<core::Sample<msg::LidarScan>> lidar;  // 64 KiB: not on the stack
  // UTC minus the recorder clock at start: message log times and viewer stamps are UTC.
  core::TimeNs utc_offset_ns = 0;

  [[nodiscard]] core::TimeNs utc(core::TimeNs stamp_ns) const { return stamp_ns + utc_offset_ns; }
  core::TimeNs last_chunk_ns = 0;
  core::TimeNs last_drop_log_ns = 0;
  // The track drawn in /viz/map (navigation frame) and when the map was last written.
  TrackLine track;
  bool map_written = false;
  core::TimeNs last_map_ns = 0;
  // When the next /viz/scene and /tf, and the next /viz/scan, are due.
  VizSchedule tick_viz;
  VizSchedule scan_viz;
  std::array<std::uint64_t, kRecordChannelCount> dropped_logged{};
  bool failure_reported = false;
};

/// Everything only the sampler thread touches.
struct Recorder::SamplerState {
  std::unique_ptr<core::Sample<msg::LidarScan>> lidar =
      std::make_unique<core::Sample<msg::LidarScan>>();
  // Last store sequence queued per sampled slot.
  std::uint64_t seq_gnss = 0, seq_imu = 0, seq_lidar = 0, seq_camera = 0, seq_arduino = 0,
                seq_operator = 0;
  std::array<std::uint64_t, msg::kDeviceCount> seq_health{};
};

namespace {

void write_metadata_records(McapWriter& w, const MetadataRecords& records) {
  for (const auto& [name, values] : records) {
    McapMetadataMap map;
    for (const auto& [key, value] : values) map.emplace(key, value);
    (void)w.write_metadata(name, map);  // a failure shows in the writer's state
  }
}

class RecorderLogSink final : public spdlog::sinks::base_sink<std::mutex> {
 public:
  explicit RecorderLogSink(
      std::shared_ptr<void> keep_alive,
      std::function<void(core::TimeNs, int, std::string_view, std::string_view)> push)
      : keep_alive_(std::move(keep_alive)), push_(std::move(push)) {}

 protected:
  void sink_it_(const spdlog::details::log_msg& msg) override {
    push_(0, static_cast<int>(msg.level),
          std::string_view(msg.logger_name.data(), msg.logger_name.size()),
          std::string_view(msg.payload.data(), msg.payload.size()));
  }
  void flush_() override {}

 private:
  std::shared_ptr<void> keep_alive_;
  std::function<void(core::TimeNs, int, std::string_view, std::string_view)> push_;
};

foxglove::LogLevel to_foxglove_level(int spdlog_level) {
  switch (static_cast<spdlog::level::level_enum>(spdlog_level)) {
    case spdlog::level::trace:
    case spdlog::level::debug:
      return foxglove::LogLevel::kDebug;
    case spdlog::level::info:
      return foxglove::LogLevel::kInfo;
    case spdlog::level::warn:
      return foxglove::LogLevel::kWarning;
    case spdlog::level::err:
      return foxglove::LogLevel::kError;
    case spdlog::level::critical:
      return foxglove::LogLevel::kFatal;
    default:
      return foxglove::LogLevel::kUnknown;
  }
}

}  // namespace

Recorder::Recorder(RecorderOptions options, const core::LatestStore* store,
                   const core::Clock& clock)
    : options_(std::move(options)),
      store_(store),
      clock_(clock),
      queues_(std::make_shared<Queues>(options_)),
      state_(std::make_unique<WriterState>(options_)),
      sampler_(std::make_unique<SamplerState>()) {}

Recorder::~Recorder() { stop(); }

std::shared_ptr<spdlog::sinks::sink> Recorder::log_sink() {
  // The sink keeps the queues alive and stamps lines with the writer thread's latest clock
  // reading, so it stays safe (dropping) even if it outlives the recorder.
  std::shared_ptr<Queues> q = queues_;
  Queues* raw = q.get();
  return std::make_shared<RecorderLogSink>(
      std::move(q), [raw](core::TimeNs, int level, std::string_view name, std::string_view text) {
        raw->push_log(raw->now_ns.load(std::memory_order_relaxed), level, name, text);
      });
}

bool Recorder::start() {
  if (running_.load() || thread_.joinable()) return true;
  WriterState& st = *state_;
  McapWriter& w = st.writer;
  if (!w.open(options_.path)) {
    note_failure();
    return false;
  }
  auto protobuf = [&](Layout layout) {
    return w.add_schema(proto_message_name(layout), kProtobufEncoding, file_descriptor_set(layout));
  };
  auto json_schema = [&](foxglove::Schema s) {
    return w.add_schema(foxglove::schema_name(s), foxglove::kSchemaEncoding,
                        foxglove::schema_json(s));
  };
  auto channel = [&](RecordChannel c, std::uint16_t schema, std::string_view encoding,
                     const McapMetadataMap& meta = {}) {
    st.channel_ids[static_cast<std::size_t>(c)] =
        w.add_channel(schema, channel_topic(c), encoding, meta);
  };
  const std::uint16_t raw_schema = protobuf(Layout::kRaw);
  for (std::size_t d = 0; d < msg::kDeviceCount; ++d) {
    const auto id = static_cast<msg::DeviceId>(d);
    channel(raw_channel(id), raw_schema, kProtobufEncoding,
            {{"device", std::string(msg::device_name(id))}});
  }
  channel(RecordChannel::kTick, protobuf(Layout::kTick), kProtobufEncoding);
  channel(RecordChannel::kGnss, protobuf(Layout::kGnss), kProtobufEncoding);
  channel(RecordChannel::kImu, protobuf(Layout::kImu), kProtobufEncoding);
  channel(RecordChannel::kLidar, protobuf(Layout::kLidar), kProtobufEncoding);
  channel(RecordChannel::kCamera, protobuf(Layout::kCamera), kProtobufEncoding);
  channel(RecordChannel::kArduino, protobuf(Layout::kArduino), kProtobufEncoding);
  channel(RecordChannel::kOperator, protobuf(Layout::kOperator), kProtobufEncoding);
  channel(RecordChannel::kHealth, protobuf(Layout::kHealth), kProtobufEncoding);
  channel(RecordChannel::kVizFix, json_schema(foxglove::Schema::kLocationFix),
          foxglove::kMessageEncoding);
  channel(RecordChannel::kVizScan, json_schema(foxglove::Schema::kLaserScan),
          foxglove::kMessageEncoding);
  channel(RecordChannel::kVizPose, json_schema(foxglove::Schema::kFrameTransform),
          foxglove::kMessageEncoding);
  const std::uint16_t scene_schema = json_schema(foxglove::Schema::kSceneUpdate);
  channel(RecordChannel::kVizScene, scene_schema, foxglove::kMessageEncoding);
  channel(RecordChannel::kLog, json_schema(foxglove::Schema::kLog), foxglove::kMessageEncoding);
  channel(RecordChannel::kParams, protobuf(Layout::kParameters), kProtobufEncoding);
  channel(RecordChannel::kVizMap, scene_schema, foxglove::kMessageEncoding);  // one schema
  channel(RecordChannel::kMapGeoJson, json_schema(foxglove::Schema::kGeoJson),
          foxglove::kMessageEncoding);
  channel(RecordChannel::kCameraImage, json_schema(foxglove::Schema::kCompressedImage),
          foxglove::kMessageEncoding);
  channel(RecordChannel::kCameraAnnotations, json_schema(foxglove::Schema::kImageAnnotations),
          foxglove::kMessageEncoding);

  const core::TimeNs now_ns = clock_.now_ns();
  const auto utc_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
                          std::chrono::system_clock::now().time_since_epoch())
                          .count();
  st.utc_offset_ns = utc_ns - now_ns;
  w.write_metadata("coxswain", {{"build_version", options_.build_version},
                                {"layout_version", std::to_string(kLayoutVersion)},
                                {"encoding", std::string(kProtobufEncoding)},
                                {"clock_ns_at_start", std::to_string(now_ns)},
                                {"utc_ns_at_start", std::to_string(utc_ns)},
                                {"log_time_offset_ns", std::to_string(st.utc_offset_ns)},
                                {"stamps",
                                 "log_time = UTC nanoseconds = steady stamp + log_time_offset_ns; "
                                 "the messages' own stamp fields are the steady clock"}});
  w.write_metadata("config", {{"yaml", options_.config_yaml}});
  write_metadata_records(w, options_.extra_metadata);
  if (!w.close_chunk() || w.failed()) {
    note_failure();
    w.close();
    return false;
  }
  st.last_chunk_ns = now_ns;
  st.last_drop_log_ns = now_ns;
  queues_->now_ns.store(now_ns, std::memory_order_relaxed);
  stop_.store(false);
  running_.store(true, std::memory_order_release);
  accepting_.store(true, std::memory_order_release);
  queues_->log_accepting.store(true, std::memory_order_release);
  sampler_stop_.store(false);
  // Named, so `top -H` and /proc/PID/task show what the recorder costs apart from the rest.
  thread_ = std::thread([this] {
    ::pthread_setname_np(::pthread_self(), "cx-rec-writer");
    run();
  });
  if (store_ != nullptr && options_.sampler_thread) {
    sampler_thread_ = std::thread([this] {
      ::pthread_setname_np(::pthread_self(), "cx-rec-sampler");
      run_sampler();
    });
  }
  return true;
}

void Recorder::stop(MetadataRecords closing_metadata) {
  if (!thread_.joinable()) return;
  accepting_.store(false, std::memory_order_release);
  queues_->log_accepting.store(false, std::memory_order_release);
  // The sampler first (it takes a last look at the store), then the writer drains everything.
  if (sampler_thread_.joinable()) {
    {
      std::lock_guard lock(stop_mutex_);
      sampler_stop_.store(true, std::memory_order_release);
    }
    stop_cv_.notify_all();
    sampler_thread_.join();
  } else if (store_ != nullptr) {
    (void)sample_store();  // the last look the sampler thread would have taken
  }
  {
    std::lock_guard lock(stop_mutex_);
    closing_metadata_ = std::move(closing_metadata);
    stop_.store(true, std::memory_order_release);
  }
  stop_cv_.notify_all();
  thread_.join();
  running_.store(false, std::memory_order_release);
}

void Recorder::on_raw(msg::DeviceId device, drivers::RawDirection direction, core::TimeNs stamp_ns,
                      std::span<const std::uint8_t> bytes) noexcept {
  const auto d = static_cast<std::size_t>(device);
  if (d >= msg::kDeviceCount) return;
  const RecordChannel ch = raw_channel(device);
  if (!accepting_.load(std::memory_order_acquire)) {
    count_drop(ch);
    return;
  }
  auto& ring = queues_->raw[d];
  while (!bytes.empty()) {
    RawSlot* s = ring.try_claim();
    if (s == nullptr) {
      count_drop(ch, (bytes.size() + kRawSlotBytes - 1) / kRawSlotBytes);
      return;
    }
    const std::size_t n = std::min(bytes.size(), kRawSlotBytes);
    s->stamp_ns = stamp_ns;
    s->direction = direction;
    s->length = static_cast<std::uint16_t>(n);
    std::memcpy(s->bytes.data(), bytes.data(), n);
    ring.publish();
    bytes = bytes.subspan(n);
  }
}

bool Recorder::record_tick(const TickInput& tick) noexcept {
  if (tick.snapshot == nullptr) return false;
  if (!accepting_.load(std::memory_order_acquire)) {
    count_drop(RecordChannel::kTick);
    return false;
  }
  TickSlot* s = queues_->tick.try_claim();
  if (s == nullptr) {
    count_drop(RecordChannel::kTick);
    if (tick.viz != nullptr) count_drop(RecordChannel::kVizScene);
    return false;
  }
  const std::size_t n = proto::encode_tick(s->bytes, tick.tick_index, tick.now_ns, *tick.snapshot,
                                           tick.command, tick.state_path);
  s->now_ns = tick.now_ns;
  s->length = static_cast<std::uint16_t>(n);
  s->state_path_length =
      static_cast<std::uint16_t>(std::min(tick.state_path.size(), kMaxStatePathBytes));
  // An empty string_view may hold a null pointer, which memcpy must not be given.
  if (s->state_path_length > 0) {
    std::memcpy(s->state_path.data(), tick.state_path.data(), s->state_path_length);
  }
  s->has_viz = tick.viz != nullptr;
  if (s->has_viz) s->viz = *tick.viz;
  queues_->tick.publish();
  return true;
}

bool Recorder::record_parameters(std::uint64_t tick_index, core::TimeNs stamp_ns,
                                 std::span<const NamedValue> values) noexcept {
  if (!accepting_.load(std::memory_order_acquire)) {
    count_drop(RecordChannel::kParams);
    return false;
  }
  ParamsSlot* s = queues_->params.try_claim();
  if (s == nullptr) {
    count_drop(RecordChannel::kParams);
    return false;
  }
  const std::size_t n = proto::encode_parameters(s->bytes, tick_index, stamp_ns, values);
  if (n == 0) {
    count_drop(RecordChannel::kParams);  // the claimed slot is reused by the next call
    return false;
  }
  s->stamp_ns = stamp_ns;
  s->length = static_cast<std::uint32_t>(n);
  queues_->params.publish();
  return true;
}

bool Recorder::record_image(core::TimeNs stamp_ns, std::span<const std::uint8_t> jpeg,
                            const msg::CameraDetections& detections, double scale) noexcept {
  if (!accepting_.load(std::memory_order_acquire) || jpeg.size() > kMaxImageBytes) {
    count_drop(RecordChannel::kCameraImage);
    return false;
  }
  ImageSlot* s = queues_->images.try_claim();
  if (s == nullptr) {
    count_drop(RecordChannel::kCameraImage);
    return false;
  }
  if (!jpeg.empty()) std::memcpy(s->bytes.get(), jpeg.data(), jpeg.size());
  s->length = static_cast<std::uint32_t>(jpeg.size());
  s->stamp_ns = stamp_ns;
  s->scale = scale;
  s->detections = detections;
  queues_->images.publish();
  return true;
}

bool Recorder::record_log(core::TimeNs stamp_ns, int spdlog_level, std::string_view logger,
                          std::string_view text) noexcept {
  return queues_->push_log(stamp_ns, spdlog_level, logger, text);
}

RecorderStats Recorder::stats() const {
  RecorderStats s;
  for (std::size_t i = 0; i < kRecordChannelCount; ++i) {
    s.channels[i].written = written_[i].load(std::memory_order_relaxed);
    s.channels[i].dropped = dropped_[i].load(std::memory_order_relaxed);
  }
  s.channels[static_cast<std::size_t>(RecordChannel::kLog)].dropped +=
      queues_->log_dropped.load(std::memory_order_relaxed);
  s.raw_bytes = raw_bytes_.load(std::memory_order_relaxed);
  s.file_bytes = file_bytes_.load(std::memory_order_relaxed);
  s.chunks = chunks_.load(std::memory_order_relaxed);
  s.failed = failed_.load(std::memory_order_acquire);
  s.running = running_.load(std::memory_order_acquire) && !s.failed;
  {
    std::lock_guard lock(error_mutex_);
    s.error = error_;
  }
  return s;
}

void Recorder::note_failure() {
  const McapWriter& w = state_->writer;
  {
    std::lock_guard lock(error_mutex_);
    error_ = w.error().empty() ? "recording failed" : w.error();
  }
  failed_.store(true, std::memory_order_release);
}

void Recorder::write(RecordChannel channel, core::TimeNs stamp_ns,
                     std::span<const std::uint8_t> data) {
  const auto c = static_cast<std::size_t>(channel);
  McapWriter& w = state_->writer;
  const core::TimeNs utc_ns = state_->utc(stamp_ns);
  const std::uint64_t log_time_ns = utc_ns < 0 ? 0U : static_cast<std::uint64_t>(utc_ns);
  if (failed_.load(std::memory_order_relaxed) ||
      !w.write_message(state_->channel_ids[c], log_time_ns, log_time_ns, data)) {
    if (!failed_.load(std::memory_order_relaxed) && w.failed()) note_failure();
    count_drop(channel);
    return;
  }
  written_[c].fetch_add(1, std::memory_order_relaxed);
}

void Recorder::write(RecordChannel channel, core::TimeNs stamp_ns, std::string_view json) {
  write(channel, stamp_ns,
        std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(json.data()),
                                      json.size()));
}

bool Recorder::drain_once() {
  WriterState& st = *state_;
  bool any = false;
  // Bounded batches per queue per pass, so one flooding device cannot starve the others.
  constexpr int kBatch = 256;
  for (std::size_t d = 0; d < msg::kDeviceCount; ++d) {
    auto& ring = queues_->raw[d];
    const auto device = static_cast<msg::DeviceId>(d);
    for (int i = 0; i < kBatch; ++i) {
      RawSlot* s = ring.front();
      if (s == nullptr) break;
      any = true;
      const RawRecord raw{device, s->direction, s->stamp_ns,
                          std::span<const std::uint8_t>(s->bytes.data(), s->length)};
      const std::size_t n = proto::encode_raw(st.scratch, raw);
      write(raw_channel(device), s->stamp_ns, std::span<const std::uint8_t>(st.scratch).first(n));
      raw_bytes_.fetch_add(s->length, std::memory_order_relaxed);
      ring.pop();
    }
  }
  for (int i = 0; i < kBatch; ++i) {
    TickSlot* s = queues_->tick.front();
    if (s == nullptr) break;
    any = true;
    write(RecordChannel::kTick, s->now_ns,
          std::span<const std::uint8_t>(s->bytes.data(), s->length));
    // The Foxglove views at most every viz_period_ns: /tick holds every tick for replay.
    if (s->has_viz && s->viz.pose_valid) st.track.add({s->viz.north_m, s->viz.east_m});
    if (s->has_viz && st.tick_viz.due(s->now_ns, options_.viz_period_ns)) {
      if (s->viz.pose_valid) {
        write(RecordChannel::kVizPose, s->now_ns,
              foxglove::frame_transform_json(st.utc(s->now_ns), s->viz));
      }
      write(RecordChannel::kVizScene, s->now_ns,
            foxglove::scene_update_json(
                st.utc(s->now_ns), s->viz,
                std::string_view(s->state_path.data(), s->state_path_length)));
      if (!st.map_written || s->now_ns - st.last_map_ns >= options_.map_period_ns) {
        st.map_written = true;
        st.last_map_ns = s->now_ns;
        write(RecordChannel::kVizMap, s->now_ns,
              foxglove::map_scene_json(st.utc(s->now_ns), options_.map, st.track.points()));
        write(RecordChannel::kMapGeoJson, s->now_ns, foxglove::geojson_json(options_.map));
      }
    }
    queues_->tick.pop();
  }
  for (int i = 0; i < kBatch; ++i) {
    ImageSlot* s = queues_->images.front();
    if (s == nullptr) break;
    any = true;
    const core::TimeNs t = st.utc(s->stamp_ns);
    write(RecordChannel::kCameraImage, s->stamp_ns,
          foxglove::compressed_image_json(
              t, std::span<const std::uint8_t>(s->bytes.get(), s->length)));
    write(RecordChannel::kCameraAnnotations, s->stamp_ns,
          foxglove::image_annotations_json(t, s->detections, s->scale));
    queues_->images.pop();
  }
  for (int i = 0; i < kBatch; ++i) {
    ParamsSlot* s = queues_->params.front();
    if (s == nullptr) break;
    any = true;
    write(RecordChannel::kParams, s->stamp_ns,
          std::span<const std::uint8_t>(s->bytes.data(), s->length));
    queues_->params.pop();
  }
  for (int i = 0; i < kBatch; ++i) {
    LogSlot* s = queues_->log.front();
    if (s == nullptr) break;
    any = true;
    write(RecordChannel::kLog, s->stamp_ns,
          foxglove::log_json(st.utc(s->stamp_ns), to_foxglove_level(s->level),
                             std::string_view(s->name.data(), s->name_length),
                             std::string_view(s->text.data(), s->text_length)));
    queues_->log.pop();
  }
  for (int i = 0; i < kBatch; ++i) {
    SampleSlot* s = queues_->samples.front();
    if (s == nullptr) break;
    any = true;
    const std::span<const std::uint8_t> data(s->bytes.data(), s->length);
    write(s->channel, s->stamp_ns, data);
    if (s->channel == RecordChannel::kGnss) {
      std::uint64_t seq = 0;
      msg::GnssFix fix;
      if (proto::decode_sample(data, seq, fix)) {
        fix.stamp_ns = st.utc(fix.stamp_ns);
        write(RecordChannel::kVizFix, s->stamp_ns, foxglove::location_fix_json(fix));
      }
    }
    queues_->samples.pop();
  }
  for (int i = 0; i < kBatch; ++i) {
    LidarSampleSlot* s = queues_->lidar_samples.front();
    if (s == nullptr) break;
    any = true;
    const std::span<const std::uint8_t> data(s->bytes.data(), s->length);
    write(RecordChannel::kLidar, s->stamp_ns, data);
    std::uint64_t seq = 0;
    if (st.scan_viz.due(s->stamp_ns, options_.viz_period_ns) &&
        proto::decode_sample(data, seq, st.lidar->value)) {
      st.lidar->value.stamp_ns = st.utc(st.lidar->value.stamp_ns);
      write(RecordChannel::kVizScan, s->stamp_ns,
            foxglove::laser_scan_json(st.lidar->value, options_.scan_viz_bins));
    }
    queues_->lidar_samples.pop();
  }
  return any;
}

bool Recorder::sample_store() {
  SamplerState& st = *sampler_;
  bool any = false;
  // Queues a slot's value when its sequence moved; a jump of more than one is a drop.
  auto sample = [&](const auto& slot, auto& sample_out, std::uint64_t& last, RecordChannel ch) {
    if (slot.sequence() == last) return;
    slot.read(sample_out);
    if (sample_out.sequence <= last) return;
    if (sample_out.sequence > last + 1) count_drop(ch, sample_out.sequence - last - 1);
    last = sample_out.sequence;
    any = true;
    SampleSlot* s = queues_->samples.try_claim();
    if (s == nullptr) {
      count_drop(ch);
      return;
    }
    s->channel = ch;
    s->stamp_ns = sample_out.stamp_ns;
    s->length = static_cast<std::uint32_t>(
        proto::encode_sample(s->bytes, sample_out.sequence, sample_out.value));
    queues_->samples.publish();
  };
  core::Sample<msg::GnssFix> gnss;
  sample(store_->gnss, gnss, st.seq_gnss, RecordChannel::kGnss);
  core::Sample<msg::ImuSample> imu;
  sample(store_->imu, imu, st.seq_imu, RecordChannel::kImu);
  core::Sample<msg::CameraDetections> camera;
  sample(store_->camera, camera, st.seq_camera, RecordChannel::kCamera);
  core::Sample<msg::ArduinoStatus> arduino;
  sample(store_->arduino, arduino, st.seq_arduino, RecordChannel::kArduino);
  core::Sample<msg::OperatorInput> op;
  sample(store_->operator_input, op, st.seq_operator, RecordChannel::kOperator);
  for (std::size_t d = 0; d < msg::kDeviceCount; ++d) {
    core::Sample<msg::DeviceHealth> health;
    sample(store_->health[d], health, st.seq_health[d], RecordChannel::kHealth);
  }
  // Scans go to their own queue of large slots.
  if (store_->lidar.sequence() != st.seq_lidar) {
    core::Sample<msg::LidarScan>& scan = *st.lidar;
    store_->lidar.read(scan);
    if (scan.sequence > st.seq_lidar) {
      if (scan.sequence > st.seq_lidar + 1) {
        count_drop(RecordChannel::kLidar, scan.sequence - st.seq_lidar - 1);
      }
      st.seq_lidar = scan.sequence;
      any = true;
      LidarSampleSlot* s = queues_->lidar_samples.try_claim();
      if (s == nullptr) {
        count_drop(RecordChannel::kLidar);
      } else {
        s->stamp_ns = scan.stamp_ns;
        s->length =
            static_cast<std::uint32_t>(proto::encode_sample(s->bytes, scan.sequence, scan.value));
        queues_->lidar_samples.publish();
      }
    }
  }
  return any;
}

void Recorder::sample() noexcept {
  if (store_ == nullptr || options_.sampler_thread || !accepting_.load(std::memory_order_acquire)) {
    return;
  }
  (void)sample_store();
}

std::size_t Recorder::queue_room() const {
  // One pass queues at most one message per small store slot and one scan.
  constexpr std::size_t kSlotsPerPass = 5 + msg::kDeviceCount;
  const std::size_t samples = queues_->samples.capacity() - queues_->samples.size();
  const std::size_t scans = queues_->lidar_samples.capacity() - queues_->lidar_samples.size();
  return std::min(samples / kSlotsPerPass, scans);
}

void Recorder::run_sampler() {
  for (;;) {
    const bool stopping = sampler_stop_.load(std::memory_order_acquire);
    sample_store();
    if (stopping) break;  // the pass above saw everything published before stop()
    std::unique_lock lock(stop_mutex_);
    stop_cv_.wait_for(lock, std::chrono::nanoseconds(options_.sample_period_ns),
                      [this] { return sampler_stop_.load(std::memory_order_acquire); });
  }
}

void Recorder::log_drops(bool force) {
  WriterState& st = *state_;
  const core::TimeNs now_ns = queues_->now_ns.load(std::memory_order_relaxed);
  if (!force && now_ns - st.last_drop_log_ns < options_.drop_log_period_ns) return;
  st.last_drop_log_ns = now_ns;
  const RecorderStats s = stats();
  for (std::size_t i = 0; i < kRecordChannelCount; ++i) {
    const std::uint64_t total = s.channels[i].dropped;
    if (total == st.dropped_logged[i]) continue;
    spdlog::warn("recorder: dropped {} messages on {} (total {})", total - st.dropped_logged[i],
                 channel_topic(static_cast<RecordChannel>(i)), total);
    st.dropped_logged[i] = total;
  }
}

void Recorder::run() {
  WriterState& st = *state_;
  McapWriter& w = st.writer;
  auto publish_writer_stats = [&] {
    file_bytes_.store(w.stats().bytes_written, std::memory_order_relaxed);
    chunks_.store(w.stats().chunks, std::memory_order_relaxed);
  };
  for (;;) {
    const bool stopping = stop_.load(std::memory_order_acquire);
    const core::TimeNs now_ns = clock_.now_ns();
    queues_->now_ns.store(now_ns, std::memory_order_relaxed);
    const bool busy = drain_once();
    if (!failed_.load(std::memory_order_relaxed) &&
        now_ns - st.last_chunk_ns >= options_.chunk_period_ns) {
      st.last_chunk_ns = now_ns;
      if (!w.close_chunk()) note_failure();
      publish_writer_stats();
    }
    if (failed_.load(std::memory_order_relaxed) && !st.failure_reported) {
      st.failure_reported = true;
      spdlog::error("recorder: recording stopped, the run continues: {}", stats().error);
    }
    log_drops(false);
    if (stopping && !busy) break;  // the stop flag was seen before a pass that found nothing
    if (!busy) {
      std::unique_lock lock(stop_mutex_);
      stop_cv_.wait_for(lock, std::chrono::nanoseconds(options_.idle_sleep_ns),
                        [this] { return stop_.load(std::memory_order_acquire); });
    }
  }
  log_drops(true);
  // Lines logged by log_drops above are still in the queue: one more pass takes them.
  drain_once();
  {
    std::lock_guard lock(stop_mutex_);
    write_metadata_records(w, closing_metadata_);
  }
  if (!failed_.load(std::memory_order_relaxed)) {
    if (!w.close()) note_failure();
  } else {
    w.close();
  }
  publish_writer_stats();
}

}  // namespace coxswain::record
