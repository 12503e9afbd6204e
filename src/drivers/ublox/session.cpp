// SPDX-License-Identifier: Apache-2.0
#include "coxswain/drivers/ublox/session.hpp"

#include <algorithm>
#include <cmath>

#include "coxswain/drivers/detail_text.hpp"

namespace coxswain::drivers::ublox {

namespace {

ConfigParams params_from(const config::GnssDeviceConfig& c) {
  ConfigParams p;
  p.rate_hz = c.rate_hz;
  p.port = c.port == config::GnssPort::kUart1 ? Port::kUart1 : Port::kUsb;
  p.nmea_enabled = c.nmea_output;
  return p;
}

Generation generation_of(const config::GnssDeviceConfig& c) {
  return c.receiver == config::GnssReceiver::kM8 ? Generation::kM8 : Generation::kF9;
}

bool is_ubx(msg::GnssSource s) {
  return s == msg::GnssSource::kUbxNavPvt || s == msg::GnssSource::kUbxNavLegacy;
}
bool is_nmea(msg::GnssSource s) { return !is_ubx(s); }

// NAV-PVT on the wire: 6 header + 92 payload + 2 checksum bytes (docs/protocols.md 3.3).
constexpr std::uint64_t kNavPvtFrameBytes = 100;

}  // namespace

UbloxSession::UbloxSession(const config::GnssDeviceConfig& config,
                           core::LatestSlot<msg::GnssFix>& fixes, const SessionTiming& timing)
    : config_(config), fixes_(fixes), timing_(timing) {
  stale_after_ns_ = core::ms_to_ns(std::max<std::int64_t>(1, config.timeout_ms));
  reopen_after_ns_ = timing.reopen_after_ns > 0
                         ? timing.reopen_after_ns
                         : std::max<core::TimeNs>(10 * stale_after_ns_, 5 * core::kNsPerSec);
  const double rate = std::isfinite(config.rate_hz) && config.rate_hz > 0.0 ? config.rate_hz : 1.0;
  nmea_hold_ns_ = timing.nmea_hold_ns > 0
                      ? timing.nmea_hold_ns
                      : std::max<core::TimeNs>(core::sec_to_ns(3.0 / rate), 2'500 * core::kNsPerMs);
  timing_.max_attempts = std::max(1, timing.max_attempts);
}

void UbloxSession::set_detail(std::string_view a, std::string_view b) {
  set_detail_text(detail_, a, b);
}

void UbloxSession::on_open(DeviceLink& link, core::TimeNs now_ns) {
  open_ = true;
  opened_ns_ = now_ns;
  last_now_ns_ = now_ns;
  last_frame_ns_ = core::kNeverNs;
  last_pvt_ns_ = core::kNeverNs;
  last_gga_ns_ = core::kNeverNs;
  rate_.clear();
  decoder_.reset();
  chunk_count_ = 0;
  config_failures_ = 0;
  step_ = 0;
  const ConfigParams params = params_from(config_);
  const Generation gen = generation_of(config_);
  if (const auto bad = params.validate(gen)) {
    // Nothing sensible to send; decode whatever the receiver is set up to emit.
    plan_ = ConfigPlan{};
    set_detail("not configured: ", *bad);
    return;
  }
  plan_ = make_config_plan(gen, params);
  set_detail("configuring");
  if (plan_.count > 0) {
    attempts_ = 0;
    send_step(link, now_ns);
  }
}

void UbloxSession::send_step(DeviceLink& link, core::TimeNs now_ns) {
  ++attempts_;
  step_sent_ns_ = now_ns;
  // A full write queue loses the frame; the ACK timeout then retries it like a lost ACK.
  (void)link.write(plan_.steps[step_].frame.bytes());
}

void UbloxSession::finish_step(DeviceLink& link, core::TimeNs now_ns, std::string_view failure) {
  if (!failure.empty()) {
    ++config_failures_;
    // The first failure is the most useful one to show; later ones only raise the count.
    if (config_failures_ == 1) set_detail(failure, plan_.steps[step_].what);
  }
  ++step_;
  attempts_ = 0;
  if (step_ < plan_.count) {
    send_step(link, now_ns);
  } else if (config_failures_ == 0) {
    set_detail("configured");
  }
}

core::TimeNs UbloxSession::arrival_of(std::uint64_t offset) const {
  // Newest chunk whose first byte is at or before `offset`; the oldest kept one otherwise.
  core::TimeNs found = core::kNeverNs;
  for (std::size_t k = 0; k < chunk_count_; ++k) {
    const Chunk& c = chunks_[(chunk_next_ + chunks_.size() - 1 - k) % chunks_.size()];
    found = c.arrival_ns;
    if (c.start <= offset) break;
  }
  return found;
}

void UbloxSession::on_bytes(std::span<const std::uint8_t> bytes, core::TimeNs arrival_ns,
                            DeviceLink& link) {
  if (bytes.empty()) return;
  chunks_[chunk_next_] = Chunk{stream_offset_, arrival_ns};
  chunk_next_ = (chunk_next_ + 1) % chunks_.size();
  chunk_count_ = std::min(chunk_count_ + 1, chunks_.size());
  std::uint64_t frames_before = decoder_.stats().frames_ok;
  std::span<const std::uint8_t> rest = bytes;
  while (true) {
    const DecodeStep step = decoder_.decode(rest);
    // The last '$' handed to the decoder starts the NMEA sentence it may just have completed
    // (a sentence holds no other '$').
    for (std::size_t i = step.consumed; i > 0; --i) {
      if (rest[i - 1] == '$') {
        last_dollar_offset_ = stream_offset_ + i - 1;
        break;
      }
    }
    rest = rest.subspan(step.consumed);
    stream_offset_ += step.consumed;
    if (decoder_.stats().frames_ok != frames_before) {
      frames_before = decoder_.stats().frames_ok;
      last_frame_ns_ = arrival_ns;
    }
    if (step.produced) {
      const Message& m = decoder_.message();
      std::uint64_t start = stream_offset_;
      if (m.kind == MessageKind::kFix && is_nmea(m.fix.source)) {
        start = last_dollar_offset_;
      } else if (m.kind == MessageKind::kFix && m.fix.source == msg::GnssSource::kUbxNavPvt) {
        start = stream_offset_ >= kNavPvtFrameBytes ? stream_offset_ - kNavPvtFrameBytes : 0;
      }
      handle(m, arrival_of(start), link);
      continue;
    }
    if (rest.empty()) break;
  }
}

void UbloxSession::handle(const Message& m, core::TimeNs stamp_ns, DeviceLink& link) {
  switch (m.kind) {
    case MessageKind::kAck:
    case MessageKind::kNak:
      if (configuring() && m.ubx == plan_.steps[step_].ack_for) {
        finish_step(link, last_now_ns_, m.kind == MessageKind::kNak ? "NAK for " : "");
      }
      return;
    case MessageKind::kFix: {
      msg::GnssFix fix = m.fix;
      const bool hold_by_pvt =
          last_pvt_ns_ != core::kNeverNs && stamp_ns - last_pvt_ns_ < nmea_hold_ns_;
      const bool hold_by_gga =
          last_gga_ns_ != core::kNeverNs && stamp_ns - last_gga_ns_ < nmea_hold_ns_;
      if (is_ubx(fix.source)) {
        last_pvt_ns_ = stamp_ns;
      } else if (fix.source == msg::GnssSource::kNmeaGga) {
        if (hold_by_pvt) {
          ++fixes_suppressed_;
          return;
        }
        last_gga_ns_ = stamp_ns;
      } else if (is_nmea(fix.source) && (hold_by_pvt || hold_by_gga)) {
        ++fixes_suppressed_;
        return;
      }
      fix.stamp_ns = stamp_ns;
      fixes_.publish(fix, stamp_ns);
      ++fixes_published_;
      rate_.add(stamp_ns);
      return;
    }
    default:
      return;
  }
}

SessionVerdict UbloxSession::on_poll(DeviceLink& link, core::TimeNs now_ns) {
  last_now_ns_ = now_ns;
  if (configuring() && now_ns - step_sent_ns_ >= timing_.ack_timeout_ns) {
    if (attempts_ < timing_.max_attempts) {
      send_step(link, now_ns);
    } else {
      finish_step(link, now_ns, "no ACK for ");
    }
  }
  if (rtcm_ != nullptr) {
    // Whole frames while the link takes them; a refused frame (write queue full) stays queued
    // for the next poll, so a burst is paced by the port instead of being cut.
    while (const RtcmQueue::Slot* s = rtcm_->front()) {
      if (!link.write(s->view())) break;
      ++rtcm_forwarded_;
      rtcm_->release();
    }
  }
  const core::TimeNs since = last_frame_ns_ != core::kNeverNs ? last_frame_ns_ : opened_ns_;
  if (since != core::kNeverNs && now_ns - since > reopen_after_ns_) {
    set_detail("silent too long: reopening");
    return SessionVerdict::kReopen;
  }
  return SessionVerdict::kContinue;
}

void UbloxSession::on_close(core::TimeNs /*now_ns*/) {
  open_ = false;
  decoder_.reset();
  chunk_count_ = 0;
}

void UbloxSession::fill_health(msg::DeviceHealth& health, core::TimeNs now_ns) const {
  const CodecStats& s = decoder_.stats();
  health.device = msg::DeviceId::kGnss;
  health.frames_ok = s.frames_ok;
  health.checksum_errors = s.checksum_errors;
  health.framing_errors = s.framing_errors;
  health.last_frame_ns = last_frame_ns_;
  health.rate_hz = rate_.rate_hz(now_ns, timing_.rate_window_ns);
  const core::TimeNs since = last_frame_ns_ != core::kNeverNs ? last_frame_ns_ : opened_ns_;
  if (!open_) {
    health.state = msg::DeviceState::kOpening;
  } else if (configuring()) {
    health.state = msg::DeviceState::kConfiguring;
  } else if (since == core::kNeverNs || now_ns - since > stale_after_ns_) {
    health.state = msg::DeviceState::kStale;
  } else if (last_frame_ns_ == core::kNeverNs) {
    health.state = msg::DeviceState::kConfiguring;  // plan done, nothing received yet
  } else {
    health.state = msg::DeviceState::kRunning;
  }
  health.set_detail(std::string_view(detail_.data()));
}

}  // namespace coxswain::drivers::ublox
