// SPDX-License-Identifier: Apache-2.0
#include "sim/devices/arduino/emulator.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace coxswain::sim::devices::arduino {

std::optional<std::string> EmulatorFaults::validate() const {
  const auto prob_ok = [](double p) { return std::isfinite(p) && p >= 0.0 && p <= 1.0; };
  if (!prob_ok(garbage_probability)) return std::string("garbage_probability must be in [0, 1]");
  if (!prob_ok(corrupt_probability)) return std::string("corrupt_probability must be in [0, 1]");
  return std::nullopt;
}

std::optional<std::string> EmulatorConfig::validate() const {
  if (const char* e = logic.validate()) return std::string(e);
  if (bootloader_ms < 0) return std::string("bootloader_ms must be >= 0");
  if (telemetry_period_ms == 0) return std::string("telemetry_period_ms must be > 0");
  return faults.validate();
}

Emulator::Emulator(const EmulatorConfig& config)
    : config_(config),
      inputs_(config.inputs),
      logic_(config.logic),
      rng_state_(config.faults.seed) {}

std::uint64_t Emulator::next_random() {  // splitmix64
  std::uint64_t z = (rng_state_ += 0x9E3779B97F4A7C15ULL);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

double Emulator::uniform() {
  return static_cast<double>(next_random() >> 11) * (1.0 / 9007199254740992.0);
}

std::uint32_t Emulator::millis(core::TimeNs now_ns) const {
  // Arduino millis(): milliseconds since the reset, wrapping at 2^32.
  return static_cast<std::uint32_t>(static_cast<std::uint64_t>((now_ns - reset_ns_) / 1'000'000));
}

bool Emulator::in_bootloader(core::TimeNs now_ns) const {
  return !powered_ || now_ns < reset_ns_ + core::ms_to_ns(config_.bootloader_ms);
}

void Emulator::reset(core::TimeNs now_ns) {
  powered_ = true;
  booted_ = false;
  reset_ns_ = now_ns;
  ++stats_.resets;
  rx_.reset();
  outputs_ = fw::LogicOutputs{};  // no PWM signal while the bootloader runs
}

void Emulator::power_on_if_needed(core::TimeNs now_ns) {
  if (!powered_) reset(now_ns);
}

void Emulator::put(std::span<const std::uint8_t> bytes) {
  if (config_.faults.silent) return;
  const std::size_t room = out_.size() - out_len_;
  const std::size_t n = std::min(room, bytes.size());
  std::memcpy(out_.data() + out_len_, bytes.data(), n);
  out_len_ += n;
  stats_.dropped_bytes += bytes.size() - n;
}

void Emulator::send_frame(std::size_t n, bool telemetry) {
  ++tx_seq_;  // the sketch counts every frame it tries to send
  if (n == 0) return;
  const EmulatorFaults& f = config_.faults;
  if (telemetry && f.garbage_probability > 0.0 && uniform() < f.garbage_probability) {
    std::array<std::uint8_t, 16> junk{};
    const std::size_t k = 1 + static_cast<std::size_t>(next_random() % junk.size());
    for (std::size_t i = 0; i < k; ++i) junk[i] = static_cast<std::uint8_t>(next_random());
    put({junk.data(), k});
    ++stats_.garbage_bursts;
  }
  if (telemetry && f.corrupt_probability > 0.0 && uniform() < f.corrupt_probability) {
    // A bit inside len..payload (covered by the CRC).
    const std::size_t bit = next_random() % ((n - 4) * 8);
    tx_[2 + bit / 8] = static_cast<std::uint8_t>(tx_[2 + bit / 8] ^ (1U << (bit % 8)));
    ++stats_.corrupted_frames;
  }
  put({tx_.data(), n});
}

void Emulator::setup(std::uint32_t now_ms) {
  // The sketch's setup(): neutral PWM starts, logic reset (boot hold), Ready sent.
  booted_ = true;
  logic_.reset(now_ms);
  last_loop_ms_ = now_ms;
  last_telemetry_ms_ = now_ms;
  fw::SwitchInputs in{inputs_.estop, inputs_.start_switch};
  outputs_ = logic_.step(now_ms, in);
  fw::Ready r{};
  const fw::LogicConfig& c = logic_.config();
  r.protocol_version = fw::kProtocolVersion;
  r.fw_major = kFwMajor;
  r.fw_minor = kFwMinor;
  r.fw_patch = kFwPatch;
  r.failsafe_ms = c.failsafe_ms;
  r.neutral_us[0] = c.neutral_us[0];
  r.neutral_us[1] = c.neutral_us[1];
  r.reset_cause = config_.reset_cause;
  r.rc_channels = fw::kRcChannels;
  send_frame(fw::encode(r, tx_seq_, tx_.data(), tx_.size()), false);
  ++stats_.ready_sent;
}

void Emulator::loop_once(std::uint32_t now_ms) {
  if (inputs_.rc_present && now_ms % kRcFramePeriodMs == 0) {
    logic_.on_rc_pulse(now_ms, 0, inputs_.rc_steering_us);
    logic_.on_rc_pulse(now_ms, 1, inputs_.rc_throttle_us);
    logic_.on_rc_pulse(now_ms, 2, inputs_.mode_auto ? 1900 : 1100);
  }
  const fw::SwitchInputs in{inputs_.estop, inputs_.start_switch};
  outputs_ = logic_.step(now_ms, in);
  if (static_cast<std::uint32_t>(now_ms - last_telemetry_ms_) >= config_.telemetry_period_ms) {
    last_telemetry_ms_ = now_ms;
    fw::Telemetry t{};
    logic_.fill_telemetry(now_ms, outputs_, rx_.stats(), inputs_.supply_mv, &t);
    send_frame(fw::encode(t, tx_seq_, tx_.data(), tx_.size()), true);
    ++stats_.telemetry_sent;
  }
}

void Emulator::advance(core::TimeNs now_ns) {
  power_on_if_needed(now_ns);
  if (in_bootloader(now_ns)) return;
  const std::uint32_t now_ms = millis(now_ns);
  if (!booted_) setup(static_cast<std::uint32_t>(config_.bootloader_ms));
  auto pending = static_cast<std::uint32_t>(now_ms - last_loop_ms_);
  if (pending > kMaxCatchUpMs) {
    stats_.skipped_ms += pending - kMaxCatchUpMs;
    last_loop_ms_ = now_ms - kMaxCatchUpMs;
    pending = kMaxCatchUpMs;
  }
  for (std::uint32_t k = 0; k < pending; ++k) loop_once(++last_loop_ms_);
}

void Emulator::handle_frame(const fw::Frame& f, std::uint32_t now_ms) {
  // The sketch's handle_frame().
  ++stats_.host_frames;
  fw::SetOutputs cmd{};
  fw::Ping ping{};
  fw::Hello hello{};
  if (fw::parse(f, &cmd)) {
    ++stats_.set_outputs;
    (void)logic_.on_set_outputs(now_ms, f.seq, cmd);
  } else if (fw::parse(f, &ping)) {
    ++stats_.pings;
    fw::Pong p{ping.token, now_ms};
    send_frame(fw::encode(p, tx_seq_, tx_.data(), tx_.size()), false);
  } else if (fw::parse(f, &hello)) {
    ++stats_.hellos;
    logic_.on_hello();
    fw::Ready r{};
    const fw::LogicConfig& c = logic_.config();
    r.protocol_version = fw::kProtocolVersion;
    r.fw_major = kFwMajor;
    r.fw_minor = kFwMinor;
    r.fw_patch = kFwPatch;
    r.failsafe_ms = c.failsafe_ms;
    r.neutral_us[0] = c.neutral_us[0];
    r.neutral_us[1] = c.neutral_us[1];
    r.reset_cause = config_.reset_cause;
    r.rc_channels = fw::kRcChannels;
    send_frame(fw::encode(r, tx_seq_, tx_.data(), tx_.size()), false);
    ++stats_.ready_sent;
  }
}

void Emulator::receive(std::span<const std::uint8_t> host_bytes, core::TimeNs now_ns) {
  advance(now_ns);
  if (in_bootloader(now_ns)) {
    stats_.bytes_lost_in_bootloader += host_bytes.size();
    return;
  }
  const std::uint32_t now_ms = millis(now_ns);
  for (const std::uint8_t b : host_bytes) {
    if (rx_.push(b)) handle_frame(rx_.frame(), now_ms);
  }
}

std::span<const std::uint8_t> Emulator::poll(core::TimeNs now_ns) {
  if (returned_ > 0) {
    std::memmove(out_.data(), out_.data() + returned_, out_len_ - returned_);
    out_len_ -= returned_;
    returned_ = 0;
  }
  advance(now_ns);
  returned_ = out_len_;
  return {out_.data(), out_len_};
}

}  // namespace coxswain::sim::devices::arduino
