// SPDX-License-Identifier: Apache-2.0
#include "coxswain/drivers/myahrs/session.hpp"

#include <algorithm>

#include "coxswain/drivers/detail_text.hpp"

namespace coxswain::drivers::myahrs {

namespace {

HeadingConfig heading_from(const config::ImuDeviceConfig& c, const core::MountTransform& mount) {
  HeadingConfig h;
  h.mount_yaw_deg = mount.yaw_deg;
  h.declination_deg = c.declination_deg;
  return h;
}

StartupParams params_from(const config::ImuDeviceConfig& c) {
  StartupParams p;
  p.form = c.output == config::ImuOutput::kBinary ? OutputForm::kBinary : OutputForm::kAscii;
  p.rate_hz = c.rate_hz;
  p.content = Content::kRpyImu;  // yaw straight from the sensor: no quaternion conversion
  return p;
}

bool is_frame_start(std::uint8_t b) { return b == '$' || b == '~' || b == '@' || b == kDle; }

}  // namespace

MyahrsSession::MyahrsSession(const config::ImuDeviceConfig& config,
                             const core::MountTransform& imu_mount,
                             core::LatestSlot<msg::ImuSample>& samples, const SessionTiming& timing)
    : config_(config),
      samples_(samples),
      timing_(timing),
      decoder_(heading_from(config, imu_mount)) {
  stale_after_ns_ = core::ms_to_ns(std::max<std::int64_t>(1, config.timeout_ms));
  reopen_after_ns_ = timing.reopen_after_ns > 0
                         ? timing.reopen_after_ns
                         : std::max<core::TimeNs>(10 * stale_after_ns_, 5 * core::kNsPerSec);
  timing_.max_attempts = std::max(1, timing.max_attempts);
  config_error_ = params_from(config).validate();
  if (!config_error_) config_error_ = heading_from(config, imu_mount).validate();
}

void MyahrsSession::set_detail(std::string_view a, std::string_view b) {
  set_detail_text(detail_, a, b);
}

void MyahrsSession::on_open(DeviceLink& link, core::TimeNs now_ns) {
  open_ = true;
  opened_ns_ = now_ns;
  last_now_ns_ = now_ns;
  last_frame_ns_ = core::kNeverNs;
  pending_start_ns_ = core::kNeverNs;
  rate_.clear();
  decoder_.reset();
  step_ = 0;
  startup_failures_ = 0;
  if (config_error_) {
    // Nothing sensible to ask for; decode whatever the sensor is set up to emit.
    plan_ = StartupPlan{};
    set_detail("not configured: ", *config_error_);
    return;
  }
  plan_ = make_startup_plan(params_from(config_));
  set_detail("starting up");
  if (plan_.count > 0) {
    attempts_ = 0;
    send_step(link, now_ns);
  }
}

void MyahrsSession::send_step(DeviceLink& link, core::TimeNs now_ns) {
  ++attempts_;
  step_sent_ns_ = now_ns;
  // A full write queue loses the request; the timeout then retries it like a lost answer.
  (void)link.write(plan_.steps[step_].command.data());
}

void MyahrsSession::finish_step(DeviceLink& link, core::TimeNs now_ns, std::string_view failure) {
  if (!failure.empty()) {
    ++startup_failures_;
    if (startup_failures_ == 1) set_detail(failure, plan_.steps[step_].command.name());
  }
  ++step_;
  attempts_ = 0;
  if (step_ < plan_.count) {
    send_step(link, now_ns);
  } else if (startup_failures_ == 0) {
    set_detail("started");
  }
}

void MyahrsSession::on_response(const CommandResponse& r, DeviceLink& link) {
  if (r.ok && r.command == "version") {
    const auto ver = r.attribute("ver").value_or("");
    const std::size_t n = std::min(ver.size(), version_.size() - 1);
    std::copy_n(ver.begin(), n, version_.begin());
    version_[n] = '\0';
  }
  if (!configuring()) return;
  const StartupStep& step = plan_.steps[step_];
  if (is_awaited_ok(step, r)) {
    finish_step(link, last_now_ns_, {});
  } else if (!r.ok && r.command == step.awaits) {
    finish_step(link, last_now_ns_, "ERROR answer to @");
  }
}

void MyahrsSession::on_bytes(std::span<const std::uint8_t> bytes, core::TimeNs arrival_ns,
                             DeviceLink& link) {
  std::uint64_t frames_before = decoder_.stats().codec.frames_ok;
  std::span<const std::uint8_t> rest = bytes;
  while (!rest.empty()) {
    const DecodeStep step = decoder_.decode(rest);
    if (pending_start_ns_ == core::kNeverNs &&
        std::any_of(rest.begin(), rest.begin() + static_cast<std::ptrdiff_t>(step.consumed),
                    is_frame_start)) {
      pending_start_ns_ = arrival_ns;
    }
    rest = rest.subspan(step.consumed);
    if (decoder_.stats().codec.frames_ok != frames_before) {
      frames_before = decoder_.stats().codec.frames_ok;
      last_frame_ns_ = arrival_ns;
    }
    if (!step.produced) continue;
    const core::TimeNs stamp = pending_start_ns_ != core::kNeverNs ? pending_start_ns_ : arrival_ns;
    pending_start_ns_ = core::kNeverNs;
    if (decoder_.last_output() == Output::kSample) {
      msg::ImuSample s = decoder_.sample();
      s.stamp_ns = stamp;
      samples_.publish(s, stamp);
      ++samples_published_;
      rate_.add(stamp);
    } else if (decoder_.last_output() == Output::kResponse) {
      on_response(decoder_.response(), link);
    }
  }
}

SessionVerdict MyahrsSession::on_poll(DeviceLink& link, core::TimeNs now_ns) {
  last_now_ns_ = now_ns;
  if (configuring() && now_ns - step_sent_ns_ >= timing_.response_timeout_ns) {
    if (attempts_ < timing_.max_attempts) {
      send_step(link, now_ns);
    } else {
      finish_step(link, now_ns, "no answer to @");
    }
  }
  const core::TimeNs since = last_frame_ns_ != core::kNeverNs ? last_frame_ns_ : opened_ns_;
  if (since != core::kNeverNs && now_ns - since > reopen_after_ns_) {
    set_detail("silent too long: reopening");
    return SessionVerdict::kReopen;
  }
  return SessionVerdict::kContinue;
}

void MyahrsSession::on_close(core::TimeNs /*now_ns*/) {
  open_ = false;
  decoder_.reset();
  pending_start_ns_ = core::kNeverNs;
}

void MyahrsSession::fill_health(msg::DeviceHealth& health, core::TimeNs now_ns) const {
  const CodecStats& s = decoder_.stats().codec;
  health.device = msg::DeviceId::kImu;
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
    health.state = msg::DeviceState::kConfiguring;
  } else {
    health.state = msg::DeviceState::kRunning;
  }
  health.set_detail(std::string_view(detail_.data()));
}

}  // namespace coxswain::drivers::myahrs
