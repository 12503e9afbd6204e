// SPDX-License-Identifier: Apache-2.0
#include "coxswain/drivers/rplidar/session.hpp"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>

namespace coxswain::drivers::rplidar {
namespace {

const char* motor_name(MotorControl m, bool pwm) {
  switch (m) {
    case MotorControl::kDtr:
      return "DTR de-asserted";
    case MotorControl::kPwm:
      return pwm ? "accessory-board PWM" : "DTR de-asserted (no PWM board)";
    case MotorControl::kRpmCommand:
      return "rpm command";
    case MotorControl::kFirmware:
      return "firmware-managed";
  }
  return "?";
}

bool decodable_stream(std::uint32_t type) {
  switch (static_cast<AnswerType>(type)) {
    case AnswerType::kMeasurement:
    case AnswerType::kCapsule:
    case AnswerType::kUltraCapsule:
    case AnswerType::kDenseCapsule:
      return true;
    default:
      return false;
  }
}

}  // namespace

const char* session_step_name(SessionStep step) {
  switch (step) {
    case SessionStep::kClosed:
      return "closed";
    case SessionStep::kStopSettle:
      return "STOP";
    case SessionStep::kGetInfo:
      return "GET_INFO";
    case SessionStep::kGetHealth:
      return "GET_HEALTH";
    case SessionStep::kResetWait:
      return "RESET";
    case SessionStep::kAccBoard:
      return "GET_ACC_BOARD_FLAG";
    case SessionStep::kConfTypical:
      return "GET_LIDAR_CONF(SCAN_MODE_TYPICAL)";
    case SessionStep::kConfAnswerType:
      return "GET_LIDAR_CONF(SCAN_MODE_ANS_TYPE)";
    case SessionStep::kConfUsPerSample:
      return "GET_LIDAR_CONF(SCAN_MODE_US_PER_SAMPLE)";
    case SessionStep::kSampleRate:
      return "GET_SAMPLERATE";
    case SessionStep::kStartScan:
      return "scan start";
    case SessionStep::kScanning:
      return "scanning";
  }
  return "?";
}

RplidarSession::RplidarSession(const config::LidarDeviceConfig& config,
                               const core::MountTransform& lidar_mount,
                               core::LatestSlot<msg::LidarScan>& scans)
    : config_(config), scans_(scans) {
  ScanAssemblerParams p;
  p.mount = lidar_mount;
  assembler_.emplace(p);
  note("not opened yet");
}

void RplidarSession::note(const char* fmt, ...) {
  va_list args;
  va_start(args, fmt);
  std::vsnprintf(detail_.data(), detail_.size(), fmt, args);
  va_end(args);
}

void RplidarSession::note_running() {
  const char* kind = plan_.express ? "express" : "standard";
  char warning[48] = "";
  if (health_warning_) {
    std::snprintf(warning, sizeof warning, "; health WARNING code 0x%04X",
                  static_cast<unsigned>(health_warning_code_));
  }
  note("scanning: %s fw %u.%02u hw %u, %s mode %u answer 0x%02X, %.1f us/sample, motor %s%s",
       model_.name_view().empty() ? "unknown model" : model_.name.data(),
       static_cast<unsigned>(info_.firmware_major), static_cast<unsigned>(info_.firmware_minor),
       static_cast<unsigned>(info_.hardware), kind, static_cast<unsigned>(plan_.express_mode),
       static_cast<unsigned>(plan_.answer), plan_.sample_duration_us,
       motor_name(model_.motor, use_pwm_), warning);
}

void RplidarSession::send(DeviceLink& link, const Request& r, SessionStep next, core::TimeNs now_ns,
                          std::int64_t timeout_ms) {
  pending_ = r;
  if (r.answer) decoder_.expect(*r.answer);
  (void)link.write(r.span());  // a full queue shows up as a timeout and is retried
  step_ = next;
  deadline_ns_ = now_ns + core::ms_to_ns(timeout_ms);
}

void RplidarSession::on_open(DeviceLink& link, core::TimeNs now_ns) {
  opened_ns_ = now_ns;
  verdict_ = SessionVerdict::kContinue;
  restarts_ = 0;
  health_resets_ = 0;
  health_warning_ = false;
  assembler_->reset();
  decoder_.reset();
  // The lidar may still be streaming for a previous owner: STOP, let in-flight bytes arrive,
  // then flush them (docs/protocols.md 1.3: wait >= 1 ms; the SDK waits longer).
  attempts_ = 1;
  send(link, encode_stop(), SessionStep::kStopSettle, now_ns, kStopSettleMs);
  note("opened: STOP sent, flushing after %lld ms", static_cast<long long>(kStopSettleMs));
}

void RplidarSession::on_close(core::TimeNs /*now_ns*/) {
  step_ = SessionStep::kClosed;
  deadline_ns_ = core::kNeverNs;
  assembler_->reset();
  decoder_.reset();
  note("port closed");
}

void RplidarSession::request_info(DeviceLink& link, core::TimeNs now_ns) {
  link.flush_input();
  decoder_.reset();
  attempts_ = 1;
  send(link, encode_get_info(), SessionStep::kGetInfo, now_ns, kInfoTimeoutMs);
}

void RplidarSession::after_health(DeviceLink& link, core::TimeNs now_ns) {
  use_pwm_ = model_.motor == MotorControl::kPwm;
  if (model_.motor == MotorControl::kPwm && model_.query_acc_board) {
    attempts_ = 1;
    send(link, encode_get_acc_board_flag(), SessionStep::kAccBoard, now_ns, kCommandTimeoutMs);
    return;
  }
  plan_scan(link, now_ns);
}

void RplidarSession::plan_scan(DeviceLink& link, core::TimeNs now_ns) {
  const bool want_express = config_.scan_mode == config::LidarScanMode::kExpress ||
                            (config_.scan_mode == config::LidarScanMode::kAuto &&
                             (model_.supports_conf || model_.supports_sample_rate));
  plan_ = ScanPlan{};
  attempts_ = 1;
  if (want_express && model_.supports_conf) {
    send(link, encode_get_lidar_conf(ConfType::kScanModeTypical), SessionStep::kConfTypical, now_ns,
         kCommandTimeoutMs);
  } else if (model_.supports_sample_rate) {
    // Express without the conf protocol is the legacy express mode 0 (answer 0x82).
    plan_.express = want_express;
    plan_.answer = want_express ? AnswerType::kCapsule : AnswerType::kMeasurement;
    send(link, encode_get_sample_rate(), SessionStep::kSampleRate, now_ns, kCommandTimeoutMs);
  } else {
    // Firmware < 1.17 knows neither express scans nor GET_SAMPLERATE.
    plan_.sample_duration_us = kLegacySampleDurationUs;
    start_scan(link, now_ns);
  }
}

void RplidarSession::start_scan(DeviceLink& link, core::TimeNs now_ns) {
  switch (model_.motor) {
    case MotorControl::kDtr:
      link.set_dtr(false);  // an A1 spins with DTR low; Linux raised it on open
      break;
    case MotorControl::kPwm:
      if (use_pwm_) {
        (void)link.write(encode_set_motor_pwm(config_.motor_pwm).span());
      } else {
        link.set_dtr(false);
      }
      break;
    case MotorControl::kRpmCommand:
      (void)link.write(encode_hq_motor_speed(config_.motor_rpm).span());
      break;
    case MotorControl::kFirmware:
      break;
  }
  assembler_->set_sample_duration_us(plan_.sample_duration_us);
  assembler_->reset();
  decoder_.set_dense_sample_duration_us(
      static_cast<std::uint32_t>(std::lround(std::max(plan_.sample_duration_us, 0.0))));
  const Request r =
      plan_.express ? encode_express_scan(plan_.express_mode, plan_.answer) : encode_scan();
  attempts_ = 1;
  send(link, r, SessionStep::kStartScan, now_ns, kFirstDataTimeoutMs);
  note("%s: motor %s, %s sent (answer 0x%02X), waiting %lld ms for samples",
       model_.name_view().empty() ? "lidar" : model_.name.data(),
       motor_name(model_.motor, use_pwm_), plan_.express ? "EXPRESS_SCAN" : "SCAN",
       static_cast<unsigned>(plan_.answer), static_cast<long long>(kFirstDataTimeoutMs));
}

void RplidarSession::restart(DeviceLink& link, core::TimeNs now_ns, const char* why) {
  ++restarts_;
  ++restarts_total_;
  assembler_->reset();
  decoder_.reset();
  if (restarts_ > kMaxRestarts) {
    verdict_ = SessionVerdict::kReopen;
    step_ = SessionStep::kClosed;
    deadline_ns_ = core::kNeverNs;
    note("%s; %d RESET restarts brought no revolution: reopening the port", why, kMaxRestarts);
    return;
  }
  (void)link.write(encode_reset().span());
  step_ = SessionStep::kResetWait;
  deadline_ns_ = now_ns + core::ms_to_ns(kResetWaitMs);
  note("%s: RESET sent, restart %d/%d", why, restarts_, kMaxRestarts);
}

void RplidarSession::on_timeout(DeviceLink& link, core::TimeNs now_ns) {
  const SessionStep step = step_;
  switch (step) {
    case SessionStep::kClosed:
    case SessionStep::kScanning:
      return;
    case SessionStep::kStopSettle:
    case SessionStep::kResetWait:
      request_info(link, now_ns);
      return;
    case SessionStep::kStartScan: {
      char why[96];
      std::snprintf(why, sizeof why, "no samples within %lld ms of %s",
                    static_cast<long long>(kFirstDataTimeoutMs),
                    plan_.express ? "EXPRESS_SCAN" : "SCAN");
      restart(link, now_ns, why);
      return;
    }
    default:
      break;
  }
  if (attempts_ < kMaxAttempts) {
    ++attempts_;
    note("%s unanswered: attempt %d/%d", session_step_name(step), attempts_, kMaxAttempts);
    send(link, pending_, step, now_ns,
         step == SessionStep::kGetInfo ? kInfoTimeoutMs : kCommandTimeoutMs);
    return;
  }
  // Out of attempts: optional queries fall back, essential ones restart the lidar.
  switch (step) {
    case SessionStep::kAccBoard:
      use_pwm_ = true;  // the model table's choice for A2/A3
      plan_scan(link, now_ns);
      return;
    case SessionStep::kConfTypical:
    case SessionStep::kConfAnswerType:
    case SessionStep::kConfUsPerSample:
      // No usable scan-mode table: the standard scan works on every model.
      plan_ = ScanPlan{};
      attempts_ = 1;
      send(link, encode_get_sample_rate(), SessionStep::kSampleRate, now_ns, kCommandTimeoutMs);
      return;
    case SessionStep::kSampleRate:
      plan_.sample_duration_us = kLegacySampleDurationUs;
      start_scan(link, now_ns);
      return;
    default: {
      char why[96];
      std::snprintf(why, sizeof why, "%s unanswered after %d attempts", session_step_name(step),
                    kMaxAttempts);
      restart(link, now_ns, why);
      return;
    }
  }
}

SessionVerdict RplidarSession::on_poll(DeviceLink& link, core::TimeNs now_ns) {
  if (step_ == SessionStep::kScanning) {
    const std::int64_t silence_ms =
        std::max<std::int64_t>(static_cast<std::int64_t>(config_.timeout_ms), kStaleMs);
    if (now_ns - last_data_ns_ > core::ms_to_ns(silence_ms)) {
      char why[64];
      std::snprintf(why, sizeof why, "no samples for %lld ms",
                    static_cast<long long>((now_ns - last_data_ns_) / core::kNsPerMs));
      restart(link, now_ns, why);
    } else if (now_ns - window_start_ns_ >= core::ms_to_ns(kErrorWindowMs)) {
      const std::uint64_t errors = error_count() - window_errors_at_start_;
      const std::uint64_t frames = decoder_.stats().codec.frames_ok - window_frames_at_start_;
      window_start_ns_ = now_ns;
      window_errors_at_start_ = error_count();
      window_frames_at_start_ = decoder_.stats().codec.frames_ok;
      if (errors >= kMaxErrorsPerWindow && errors * 5 >= frames) {
        char why[96];
        std::snprintf(why, sizeof why, "%llu decoder errors against %llu good frames in %lld ms",
                      static_cast<unsigned long long>(errors),
                      static_cast<unsigned long long>(frames),
                      static_cast<long long>(kErrorWindowMs));
        restart(link, now_ns, why);
      }
    }
  } else if (step_ != SessionStep::kClosed && deadline_ns_ != core::kNeverNs &&
             now_ns >= deadline_ns_) {
    on_timeout(link, now_ns);
  }
  const SessionVerdict v = verdict_;
  verdict_ = SessionVerdict::kContinue;
  return v;
}

void RplidarSession::on_bytes(std::span<const std::uint8_t> bytes, core::TimeNs arrival_ns,
                              DeviceLink& link) {
  if (bytes.empty()) return;
  chunks_[chunk_count_ % kChunkRing] = Chunk{bytes_total_, arrival_ns};
  ++chunk_count_;
  while (!bytes.empty()) {
    const DecodeStep s = decoder_.decode(bytes);
    bytes_total_ += s.consumed;
    bytes = bytes.subspan(s.consumed);
    if (s.produced) handle(decoder_.message(), bytes_total_, link);
  }
}

core::TimeNs RplidarSession::arrival_of(std::uint64_t byte_index) const {
  const std::size_t n = std::min(chunk_count_, kChunkRing);
  core::TimeNs oldest = core::kNeverNs;
  for (std::size_t k = 0; k < n; ++k) {
    const Chunk& c = chunks_[(chunk_count_ - 1 - k) % kChunkRing];
    if (c.first_index <= byte_index) return c.arrival_ns;
    oldest = c.arrival_ns;
  }
  return oldest;
}

std::uint64_t RplidarSession::error_count() const {
  const DecoderStats& s = decoder_.stats();
  return s.codec.checksum_errors + s.codec.framing_errors + s.dense_rejected;
}

void RplidarSession::handle(const Message& m, std::uint64_t end_index, DeviceLink& link) {
  // Every answer is accepted only in the step that asked for it: a late answer to a resent
  // request is ignored.
  const core::TimeNs now_ns = arrival_of(end_index - 1);
  switch (m.kind) {
    case MessageKind::kDeviceInfo:
      if (step_ != SessionStep::kGetInfo) return;
      info_ = m.device_info;
      model_ = model_info(info_);
      assembler_->set_range_limits(model_.min_range_m, model_.max_range_m);
      attempts_ = 1;
      send(link, encode_get_health(), SessionStep::kGetHealth, now_ns, kCommandTimeoutMs);
      note("GET_INFO: model 0x%02X (%s) fw %u.%02u hw %u, range %.2f-%.1f m",
           static_cast<unsigned>(info_.model),
           model_.name_view().empty() ? "unknown" : model_.name.data(),
           static_cast<unsigned>(info_.firmware_major), static_cast<unsigned>(info_.firmware_minor),
           static_cast<unsigned>(info_.hardware), static_cast<double>(model_.min_range_m),
           static_cast<double>(model_.max_range_m));
      return;
    case MessageKind::kHealth:
      if (step_ != SessionStep::kGetHealth) return;
      if (m.health.is_error()) {
        if (health_resets_ >= kMaxHealthResets) {
          verdict_ = SessionVerdict::kReopen;
          step_ = SessionStep::kClosed;
          deadline_ns_ = core::kNeverNs;
          note("GET_HEALTH: ERROR code 0x%04X persists after %d RESETs: reopening the port",
               static_cast<unsigned>(m.health.error_code), kMaxHealthResets);
          return;
        }
        ++health_resets_;
        ++health_resets_total_;
        (void)link.write(encode_reset().span());
        decoder_.reset();
        step_ = SessionStep::kResetWait;
        deadline_ns_ = now_ns + core::ms_to_ns(kResetWaitMs);
        note("GET_HEALTH: ERROR status %u code 0x%04X (protection stop): RESET %d/%d, asking again",
             static_cast<unsigned>(m.health.status), static_cast<unsigned>(m.health.error_code),
             health_resets_, kMaxHealthResets);
        return;
      }
      if (m.health.status == static_cast<std::uint8_t>(Health::Status::kWarning)) {
        health_warning_ = true;
        health_warning_code_ = m.health.error_code;
        note("GET_HEALTH: WARNING code 0x%04X: the lidar reports a recoverable problem; scanning",
             static_cast<unsigned>(m.health.error_code));
      }
      after_health(link, now_ns);
      return;
    case MessageKind::kAccBoardFlag:
      if (step_ != SessionStep::kAccBoard) return;
      use_pwm_ = m.acc_board.pwm_supported();
      plan_scan(link, now_ns);
      return;
    case MessageKind::kLidarConf: {
      const LidarConf& c = m.lidar_conf;
      if (step_ == SessionStep::kConfTypical &&
          c.type == static_cast<std::uint32_t>(ConfType::kScanModeTypical)) {
        typical_mode_ = static_cast<std::uint16_t>(c.as_uint(2));
        attempts_ = 1;
        send(link, encode_get_lidar_conf(ConfType::kScanModeAnsType, typical_mode_),
             SessionStep::kConfAnswerType, now_ns, kCommandTimeoutMs);
      } else if (step_ == SessionStep::kConfAnswerType &&
                 c.type == static_cast<std::uint32_t>(ConfType::kScanModeAnsType)) {
        const std::uint32_t ans = c.as_uint(1);
        if (!decodable_stream(ans)) {
          // e.g. ultra-dense 0x86 on newer S-series firmware: not decoded here.
          note("typical scan mode %u answers 0x%02X (not decoded): standard scan instead",
               static_cast<unsigned>(typical_mode_), static_cast<unsigned>(ans));
          plan_ = ScanPlan{};
          attempts_ = 1;
          send(link, encode_get_sample_rate(), SessionStep::kSampleRate, now_ns, kCommandTimeoutMs);
          return;
        }
        plan_.answer = static_cast<AnswerType>(ans);
        plan_.express = plan_.answer != AnswerType::kMeasurement;
        plan_.express_mode = static_cast<std::uint8_t>(typical_mode_);
        attempts_ = 1;
        send(link, encode_get_lidar_conf(ConfType::kScanModeUsPerSample, typical_mode_),
             SessionStep::kConfUsPerSample, now_ns, kCommandTimeoutMs);
      } else if (step_ == SessionStep::kConfUsPerSample &&
                 c.type == static_cast<std::uint32_t>(ConfType::kScanModeUsPerSample)) {
        plan_.sample_duration_us = static_cast<double>(c.as_uint(4)) / 256.0;
        start_scan(link, now_ns);
      }
      return;
    }
    case MessageKind::kSampleRate:
      if (step_ != SessionStep::kSampleRate) return;
      plan_.sample_duration_us =
          plan_.express ? m.sample_rate.express_us : m.sample_rate.standard_us;
      start_scan(link, now_ns);
      return;
    case MessageKind::kNodes:
      if (step_ != SessionStep::kStartScan && step_ != SessionStep::kScanning) return;
      if (step_ == SessionStep::kStartScan) {
        step_ = SessionStep::kScanning;
        deadline_ns_ = core::kNeverNs;
        window_start_ns_ = now_ns;
        window_errors_at_start_ = error_count();
        window_frames_at_start_ = decoder_.stats().codec.frames_ok;
        errors_seen_ = error_count();
        have_error_ = false;
        revolution_first_sample_ = samples_added_;
        last_revolution_points_ = 0;
        note_running();
      }
      handle_nodes(m.nodes, end_index);
      return;
    case MessageKind::kNone:
      return;
  }
}

void RplidarSession::handle_nodes(const NodeBatch& batch, std::uint64_t end_index) {
  // Where the samples' bytes started: standard nodes are the last count x 5 bytes; a capsule's
  // samples come from the PREVIOUS capsule (decoded once its successor gives the angle step).
  std::uint64_t span = 0;
  switch (batch.source) {
    case AnswerType::kMeasurement:
      span = std::uint64_t{batch.count} * kNodeSize;
      break;
    case AnswerType::kUltraCapsule:
      span = 2 * kUltraCapsuleSize;
      break;
    default:
      span = 2 * kCapsuleSize;
      break;
  }
  const std::uint64_t first = end_index >= span ? end_index - span : 0;
  last_data_ns_ = arrival_of(end_index - 1);
  // Decoder errors are noticed here, between batches, and attributed to the sample count so far.
  if (const std::uint64_t e = error_count(); e != errors_seen_) {
    errors_seen_ = e;
    last_error_sample_ = samples_added_;
    have_error_ = true;
  }
  for (std::uint32_t i = 0; i < batch.count; ++i) {
    std::uint64_t offset = 0;
    switch (batch.source) {
      case AnswerType::kMeasurement:
        offset = std::uint64_t{i} * kNodeSize;
        break;
      case AnswerType::kCapsule:
        offset = 4 + 5 * (i / 2);
        break;
      case AnswerType::kUltraCapsule:
        offset = 4 + 4 * (i / 3);
        break;
      default:
        offset = 4 + 2 * std::uint64_t{i};
        break;
    }
    const std::uint64_t sample = samples_added_++;
    if (!assembler_->add(batch.nodes[i], arrival_of(first + offset))) continue;
    // A revolution completed; this sample starts the next one. It is damaged when an error was
    // noticed during it or shortly before its first sample: a capsule is decoded only once its
    // successor arrived, so an error can remove samples that belong after the seam while the
    // previous revolution is still open (its seam-crossing sample may be among them).
    const bool damaged =
        have_error_ && last_error_sample_ + kDecodeDelaySamples >= revolution_first_sample_;
    revolution_first_sample_ = sample;
    const msg::LidarScan& scan = assembler_->scan();
    // Samples lost without a detected error (a gap the decoder interpolated over) shrink the
    // revolution: one much smaller than its predecessor is not trusted either.
    const bool shrunk =
        last_revolution_points_ > 0 &&
        std::uint64_t{scan.point_count} * 10 < std::uint64_t{last_revolution_points_} * 9;
    last_revolution_points_ = scan.point_count;
    if (damaged || shrunk || scan.point_count < kMinPointsPerRevolution) {
      ++dropped_revolutions_;
      continue;
    }
    scans_.publish(scan, scan.stamp_ns);
    ++published_;
    restarts_ = 0;
    health_resets_ = 0;
    rev_stamps_[rev_stamp_count_ % kRateRing] = scan.stamp_ns;
    ++rev_stamp_count_;
    if (published_ == 1) note_running();
  }
}

void RplidarSession::fill_health(msg::DeviceHealth& health, core::TimeNs now_ns) const {
  const DecoderStats& s = decoder_.stats();
  health.device = msg::DeviceId::kLidar;
  health.frames_ok = s.codec.frames_ok;
  health.checksum_errors = s.codec.checksum_errors;
  health.framing_errors = s.codec.framing_errors + s.dense_rejected;
  health.dropped_frames = dropped_revolutions_;
  health.last_frame_ns = last_data_ns_;
  health.rate_hz = 0.0;
  const std::size_t n = std::min(rev_stamp_count_, kRateRing);
  if (n >= 2) {
    const core::TimeNs newest = rev_stamps_[(rev_stamp_count_ - 1) % kRateRing];
    const core::TimeNs oldest = rev_stamps_[(rev_stamp_count_ - n) % kRateRing];
    if (newest > oldest && now_ns - newest < core::kNsPerSec) {
      health.rate_hz = static_cast<double>(n - 1) / core::ns_to_sec(newest - oldest);
    }
  }
  health.set_detail(detail());
  switch (step_) {
    case SessionStep::kClosed:
      health.state = msg::DeviceState::kOpening;
      return;
    case SessionStep::kScanning: {
      const core::TimeNs silence = now_ns - last_data_ns_;
      if (silence > core::ms_to_ns(kStaleMs)) {
        health.state = msg::DeviceState::kStale;
        char text[96];
        std::snprintf(text, sizeof text, "stale: no samples for %lld ms",
                      static_cast<long long>(silence / core::kNsPerMs));
        health.set_detail(text);
      } else {
        health.state = published_ > 0 ? msg::DeviceState::kRunning : msg::DeviceState::kConfiguring;
      }
      return;
    }
    default:
      health.state = msg::DeviceState::kConfiguring;
      return;
  }
}

}  // namespace coxswain::drivers::rplidar
