// SPDX-License-Identifier: Apache-2.0
#include "sim/devices/rplidar/emulator.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <utility>

#include "coxswain/core/angles.hpp"
#include "coxswain/drivers/rplidar/answer_encoder.hpp"
#include "coxswain/drivers/rplidar/request.hpp"

namespace coxswain::sim::devices::rplidar {
namespace {

using proto::AnswerType;
using proto::Command;

constexpr std::size_t kExpressSamples = 32;
constexpr std::size_t kDenseSamples = 40;
constexpr std::uint8_t kNodeQuality = 47;  // 0..63

proto::DeviceInfo make_info(std::uint8_t model, std::uint8_t fw_major, std::uint8_t fw_minor,
                            std::uint8_t hw) {
  proto::DeviceInfo i;
  i.model = model;
  i.firmware_major = fw_major;
  i.firmware_minor = fw_minor;
  i.hardware = hw;
  for (std::size_t k = 0; k < i.serial.size(); ++k) {
    i.serial[k] = static_cast<std::uint8_t>(0xC0 + k + model);
  }
  return i;
}

void put_u16(std::uint8_t* p, std::uint16_t v) {
  p[0] = static_cast<std::uint8_t>(v & 0xFFU);
  p[1] = static_cast<std::uint8_t>(v >> 8U);
}
void put_u32(std::uint8_t* p, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<std::uint8_t>((v >> (8 * i)) & 0xFFU);
}
std::uint16_t get_u16(const std::uint8_t* p) {
  return static_cast<std::uint16_t>(p[0] | (p[1] << 8));
}
std::uint32_t get_u32(const std::uint8_t* p) {
  return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8U) |
         (static_cast<std::uint32_t>(p[2]) << 16U) | (static_cast<std::uint32_t>(p[3]) << 24U);
}

std::uint16_t angle_q6(double angle_deg) {
  return static_cast<std::uint16_t>(std::lround(angle_deg * 64.0) % (360L * 64L));
}

}  // namespace

std::string_view model_name(Model model) {
  switch (model) {
    case Model::kA1:
      return "A1";
    case Model::kA2:
      return "A2";
    case Model::kA3:
      return "A3";
    case Model::kS1:
      return "S1";
    case Model::kS2:
      return "S2";
    case Model::kC1:
      return "C1";
  }
  return "?";
}

std::optional<Model> parse_model(std::string_view name) {
  for (const Model m : {Model::kA1, Model::kA2, Model::kA3, Model::kS1, Model::kS2, Model::kC1}) {
    const std::string_view n = model_name(m);
    if (name.size() == n.size() && std::toupper(static_cast<unsigned char>(name[0])) == n[0] &&
        name[1] == n[1]) {
      return m;
    }
  }
  return std::nullopt;
}

bool ModelProfile::supports_sample_rate() const {
  return proto::model_info(info).supports_sample_rate;
}
bool ModelProfile::supports_conf() const { return proto::model_info(info).supports_conf; }

ModelProfile model_profile(Model model) {
  ModelProfile p;
  const ScanModeInfo standard{"Standard", AnswerType::kMeasurement, 500.0};
  switch (model) {
    case Model::kA1:  // A1M8, firmware 1.29: conf protocol, express legacy typical
      p.info = make_info(0x18, 1, 29, 7);
      p.modes = {standard, {"Express", AnswerType::kCapsule, 250.0}};
      break;
    case Model::kA2:  // A2M8 with firmware 1.20: GET_SAMPLERATE but no conf protocol
      p.info = make_info(0x28, 1, 20, 5);
      p.modes = {standard, {"Express", AnswerType::kCapsule, 250.0}};
      p.has_pwm_board = true;
      break;
    case Model::kA3:
      p.info = make_info(0x31, 1, 29, 6);
      p.standard_us = 250;
      p.express_us = 125;
      p.modes = {ScanModeInfo{"Standard", AnswerType::kMeasurement, 250.0},
                 ScanModeInfo{"Express", AnswerType::kCapsule, 125.0}};
      p.max_range_m = 25.0F;
      p.has_pwm_board = true;
      break;
    case Model::kS1:
      p.info = make_info(0x61, 1, 29, 18);
      p.standard_us = 108;
      p.express_us = 108;
      p.modes = {ScanModeInfo{"Standard", AnswerType::kMeasurement, 108.0},
                 ScanModeInfo{"DenseBoost", AnswerType::kDenseCapsule, 108.0}};
      p.max_range_m = 40.0F;
      break;
    case Model::kS2:
      p.info = make_info(0x71, 1, 1, 18);
      p.standard_us = 63;
      p.express_us = 31;
      p.modes = {ScanModeInfo{"Standard", AnswerType::kMeasurement, 62.5},
                 ScanModeInfo{"DenseBoost", AnswerType::kDenseCapsule, 31.25}};
      p.max_range_m = 30.0F;
      break;
    case Model::kC1:
      p.info = make_info(0x41, 1, 1, 18);
      p.standard_us = 200;
      p.express_us = 200;
      p.modes = {ScanModeInfo{"Standard", AnswerType::kMeasurement, 200.0},
                 ScanModeInfo{"DenseBoost", AnswerType::kDenseCapsule, 200.0}};
      p.max_range_m = 12.0F;
      break;
  }
  return p;
}

std::optional<std::string> EmulatorFaults::validate() const {
  const auto prob_ok = [](double p) { return std::isfinite(p) && p >= 0.0 && p <= 1.0; };
  if (!prob_ok(garbage_probability)) return std::string("garbage_probability must be in [0, 1]");
  if (!prob_ok(corrupt_probability)) return std::string("corrupt_probability must be in [0, 1]");
  return std::nullopt;
}

std::optional<std::string> EmulatorConfig::validate() const {
  if (!std::isfinite(revolution_hz) || revolution_hz < 1.0 || revolution_hz > 50.0) {
    return std::string("revolution_hz must be in [1, 50]");
  }
  if (spin_up_ms < 0 || reset_ms < 0) return std::string("spin_up_ms and reset_ms must be >= 0");
  if (health_status > 2) return std::string("health_status must be 0, 1 or 2");
  return faults.validate();
}

Emulator::Emulator(const EmulatorConfig& config)
    : config_(config),
      profile_(model_profile(config.model)),
      rng_state_(config.faults.seed),
      revolution_hz_(std::clamp(config.revolution_hz, 1.0, 50.0)),
      health_status_(config.health_status),
      health_code_(config.health_error_code),
      out_(kInitialOutputBytes) {
  ranges_.reserve(kMaxBeams);
  pending_ranges_.reserve(kMaxBeams);
}

std::uint64_t Emulator::next_random() {  // splitmix64
  std::uint64_t z = (rng_state_ += 0x9E3779B97F4A7C15ULL);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

double Emulator::uniform() {
  return static_cast<double>(next_random() >> 11) * (1.0 / 9007199254740992.0);
}

void Emulator::set_ranges(std::span<const float> ranges_m) {
  source_ = nullptr;
  const std::size_t n = std::min(ranges_m.size(), kMaxBeams);
  pending_ranges_.assign(ranges_m.begin(), ranges_m.begin() + static_cast<std::ptrdiff_t>(n));
  have_pending_ = true;
  if (ranges_.empty()) {
    ranges_.swap(pending_ranges_);
    have_pending_ = false;
  }
}

void Emulator::set_range_source(std::size_t beams, RangeSource source) {
  source_ = std::move(source);
  have_pending_ = false;
  ranges_.assign(std::min(beams, kMaxBeams), 0.0F);
  if (source_) source_(revolution_, ranges_);
}

void Emulator::set_revolution_hz(double hz) { revolution_hz_ = std::clamp(hz, 1.0, 50.0); }

void Emulator::set_health(std::uint8_t status, std::uint16_t error_code) {
  health_status_ = status;
  health_code_ = error_code;
}

bool Emulator::motor_spinning() const {
  switch (config_.model) {
    case Model::kA1:
      return !dtr_asserted_;
    case Model::kA2:
    case Model::kA3:
      return pwm_ > 0;
    default:
      return true;
  }
}

double Emulator::revolution_hz() const {
  const bool s_series = config_.model == Model::kS1 || config_.model == Model::kS2;
  if (s_series && rpm_ > 0) return std::clamp(rpm_ / 60.0, 1.0, 50.0);
  return revolution_hz_;
}

AnswerType Emulator::scan_answer() const {
  switch (scan_) {
    case ScanKind::kExpress:
      return AnswerType::kCapsule;
    case ScanKind::kDense:
      return AnswerType::kDenseCapsule;
    default:
      return AnswerType::kMeasurement;
  }
}

double Emulator::sample_us() const {
  return scan_ == ScanKind::kStandard ? profile_.modes[0].us_per_sample
                                      : profile_.modes[1].us_per_sample;
}

void Emulator::put(std::span<const std::uint8_t> bytes) {
  if (config_.faults.silent) return;
  const std::size_t room = kOutputCapacity - out_len_;
  const std::size_t n = std::min(room, bytes.size());
  if (out_len_ + n > out_.size()) {
    // Grown as output really accumulates: a few kilobytes per poll at real rates.
    out_.resize(std::min(kOutputCapacity, std::max(out_.size() * 2, out_len_ + n)));
  }
  std::memcpy(out_.data() + out_len_, bytes.data(), n);
  out_len_ += n;
  stats_.dropped_bytes += bytes.size() - n;
}

void Emulator::receive(std::span<const std::uint8_t> host_bytes, core::TimeNs now_ns) {
  produce(now_ns);  // data due before these bytes goes first
  for (const std::uint8_t b : host_bytes) {
    if (rebooting_until_ns_ != core::kNeverNs && now_ns < rebooting_until_ns_) continue;
    switch (rx_phase_) {
      case RxPhase::kSync:
        if (b == proto::kSyncByte1) rx_phase_ = RxPhase::kCommand;
        break;
      case RxPhase::kCommand:
        rx_cmd_ = b;
        rx_xor_ = static_cast<std::uint8_t>(proto::kSyncByte1 ^ b);
        if ((b & 0x80U) != 0) {
          rx_phase_ = RxPhase::kSize;
        } else {
          rx_phase_ = RxPhase::kSync;
          on_request(b, {}, now_ns);
        }
        break;
      case RxPhase::kSize:
        rx_size_ = b;
        rx_xor_ = static_cast<std::uint8_t>(rx_xor_ ^ b);
        rx_len_ = 0;
        rx_phase_ = b == 0 ? RxPhase::kChecksum : RxPhase::kPayload;
        break;
      case RxPhase::kPayload:
        rx_payload_[rx_len_++] = b;
        rx_xor_ = static_cast<std::uint8_t>(rx_xor_ ^ b);
        if (rx_len_ == rx_size_) rx_phase_ = RxPhase::kChecksum;
        break;
      case RxPhase::kChecksum:
        rx_phase_ = RxPhase::kSync;
        if (b == rx_xor_) {
          on_request(rx_cmd_, {rx_payload_.data(), rx_len_}, now_ns);
        } else {
          ++stats_.bad_requests;
        }
        break;
    }
  }
}

void Emulator::on_request(std::uint8_t cmd, std::span<const std::uint8_t> payload,
                          core::TimeNs now_ns) {
  ++stats_.requests;
  const auto c = static_cast<Command>(cmd);
  const bool scan_or_motor = c == Command::kStop || c == Command::kReset || c == Command::kScan ||
                             c == Command::kForceScan || c == Command::kExpressScan ||
                             c == Command::kSetMotorPwm || c == Command::kHqMotorSpeedCtrl;
  if (scanning() && !scan_or_motor) {
    ++stats_.ignored_requests;
    return;
  }
  const unsigned major = profile_.info.model_major();
  switch (c) {
    case Command::kStop:
      ++stats_.stops;
      scan_ = ScanKind::kNone;
      return;
    case Command::kReset:
      ++stats_.resets;
      scan_ = ScanKind::kNone;
      pwm_ = 0;
      rpm_ = 0;
      rebooting_until_ns_ = now_ns + core::ms_to_ns(config_.reset_ms);
      banner_pending_ = major == 2 || major == 3;
      rx_phase_ = RxPhase::kSync;
      if (config_.health_error_clears_on_reset) {
        health_status_ = 0;
        health_code_ = 0;
      }
      return;
    case Command::kGetInfo:
      ++stats_.info_requests;
      put(proto::encode_descriptor(AnswerType::kDevInfo));
      put(proto::encode_device_info(profile_.info));
      return;
    case Command::kGetHealth:
      ++stats_.health_requests;
      put(proto::encode_descriptor(AnswerType::kHealth));
      put(proto::encode_health({health_status_, health_code_}));
      return;
    case Command::kGetSampleRate:
      if (!profile_.supports_sample_rate()) break;
      put(proto::encode_descriptor(AnswerType::kSampleRate));
      put(proto::encode_sample_rate({profile_.standard_us, profile_.express_us}));
      return;
    case Command::kGetLidarConf:
      if (!profile_.supports_conf() || payload.size() < 4) break;
      ++stats_.conf_requests;
      answer_conf(payload);
      return;
    case Command::kGetAccBoardFlag: {
      if (major < 2 || major > 5) break;  // only A2/A3 and C units answer
      put(proto::encode_descriptor(AnswerType::kAccBoardFlag));
      std::array<std::uint8_t, 4> flag{};
      put_u32(flag.data(), profile_.has_pwm_board ? 1U : 0U);
      put(flag);
      return;
    }
    case Command::kSetMotorPwm:
      if (payload.size() != 2) break;
      pwm_ = std::min<std::uint16_t>(get_u16(payload.data()), 1023);
      stats_.motor_pwm = pwm_;
      if (pwm_ > 0 && motor_on_since_ns_ == core::kNeverNs) motor_on_since_ns_ = now_ns;
      return;
    case Command::kHqMotorSpeedCtrl:
      if (payload.size() != 2) break;
      rpm_ = get_u16(payload.data());
      stats_.motor_rpm = rpm_;
      return;
    case Command::kScan:
    case Command::kForceScan:
      if (health_status_ >= 2) break;  // protection stop: no scan until RESET
      start_scan(ScanKind::kStandard, now_ns);
      return;
    case Command::kExpressScan: {
      if (health_status_ >= 2 || payload.empty()) break;
      const std::uint8_t mode = payload[0];
      const bool a_series = major >= 1 && major <= 3;
      if (mode == 0 && a_series) {
        start_scan(ScanKind::kExpress, now_ns);  // legacy express
        return;
      }
      if (mode == 1) {
        const AnswerType ans = profile_.modes[1].answer;
        start_scan(ans == AnswerType::kDenseCapsule ? ScanKind::kDense : ScanKind::kExpress,
                   now_ns);
        return;
      }
      break;
    }
    default:
      break;
  }
  ++stats_.ignored_requests;
}

void Emulator::answer_conf(std::span<const std::uint8_t> payload) {
  const std::uint32_t type = get_u32(payload.data());
  const std::uint16_t mode = payload.size() >= 6 ? get_u16(payload.data() + 4) : 0;
  std::array<std::uint8_t, 4 + 32> a{};
  put_u32(a.data(), type);
  std::size_t n = 0;
  const bool mode_ok = mode < profile_.modes.size();
  switch (static_cast<proto::ConfType>(type)) {
    case proto::ConfType::kScanModeCount:
      put_u16(a.data() + 4, static_cast<std::uint16_t>(profile_.modes.size()));
      n = 2;
      break;
    case proto::ConfType::kScanModeTypical:
      put_u16(a.data() + 4, profile_.typical_mode);
      n = 2;
      break;
    case proto::ConfType::kScanModeUsPerSample:
      if (!mode_ok) break;
      put_u32(a.data() + 4,
              static_cast<std::uint32_t>(std::lround(profile_.modes[mode].us_per_sample * 256.0)));
      n = 4;
      break;
    case proto::ConfType::kScanModeMaxDistance:
      if (!mode_ok) break;
      put_u32(a.data() + 4, static_cast<std::uint32_t>(
                                std::lround(static_cast<double>(profile_.max_range_m) * 256.0)));
      n = 4;
      break;
    case proto::ConfType::kScanModeAnsType:
      if (!mode_ok) break;
      a[4] = static_cast<std::uint8_t>(profile_.modes[mode].answer);
      n = 1;
      break;
    case proto::ConfType::kScanModeName: {
      if (!mode_ok) break;
      const std::size_t len = std::strlen(profile_.modes[mode].name);
      std::memcpy(a.data() + 4, profile_.modes[mode].name, std::min<std::size_t>(len, 31));
      n = std::min<std::size_t>(len, 31) + 1;
      break;
    }
    case proto::ConfType::kDesiredRotFreq:
      put_u16(a.data() + 4, static_cast<std::uint16_t>(std::lround(revolution_hz_ * 60.0)));
      put_u16(a.data() + 6, proto::kDefaultMotorPwm);
      n = 4;
      break;
  }
  if (n == 0) {
    ++stats_.ignored_requests;
    return;
  }
  put(proto::encode_descriptor(AnswerType::kLidarConf, static_cast<std::uint32_t>(4 + n),
                               proto::SendMode::kSingle));
  put({a.data(), 4 + n});
}

void Emulator::start_scan(ScanKind kind, core::TimeNs now_ns) {
  ++stats_.scans_started;
  scan_ = kind;
  put(proto::encode_descriptor(scan_answer()));
  capsule_n_ = 0;
  first_capsule_ = true;
  revolution_start_ = true;
  // Samples flow once the motor has spun up (the real unit waits for stable rotation).
  next_sample_ns_ = now_ns + core::ms_to_ns(config_.spin_up_ms);
}

void Emulator::new_revolution() {
  ++revolution_;
  ++stats_.revolutions;
  if (have_pending_) {
    ranges_.swap(pending_ranges_);
    have_pending_ = false;
  } else if (source_) {
    source_(revolution_, ranges_);
  }
}

float Emulator::range_at(double angle_deg) const {
  if (ranges_.empty()) return 0.0F;
  const auto n = static_cast<std::int64_t>(ranges_.size());
  const std::int64_t beam = std::llround(angle_deg / 360.0 * static_cast<double>(n)) % n;
  const float r = ranges_[static_cast<std::size_t>(beam < 0 ? beam + n : beam)];
  if (!std::isfinite(r) || r <= 0.0F || r > profile_.max_range_m) return 0.0F;
  return r;
}

void Emulator::produce(core::TimeNs now_ns) {
  if (!motor_spinning()) {
    motor_on_since_ns_ = core::kNeverNs;
    return;
  }
  if (motor_on_since_ns_ == core::kNeverNs) motor_on_since_ns_ = now_ns;
  if (scan_ == ScanKind::kNone) return;
  const core::TimeNs ready_ns = motor_on_since_ns_ + core::ms_to_ns(config_.spin_up_ms);
  next_sample_ns_ = std::max(next_sample_ns_, ready_ns);
  if (now_ns < next_sample_ns_) return;
  const double period_ns = sample_us() * 1000.0;
  auto due =
      static_cast<std::uint64_t>(static_cast<double>(now_ns - next_sample_ns_) / period_ns) + 1;
  if (due > kMaxSamplesPerPoll) {
    stats_.skipped_samples += due - kMaxSamplesPerPoll;
    next_sample_ns_ +=
        static_cast<core::TimeNs>(static_cast<double>(due - kMaxSamplesPerPoll) * period_ns);
    due = kMaxSamplesPerPoll;
  }
  const double step_deg = 360.0 * revolution_hz() * sample_us() * 1e-6;
  for (std::uint64_t k = 0; k < due; ++k) {
    emit_sample(angle_deg_, range_at(angle_deg_), revolution_start_);
    revolution_start_ = false;
    angle_deg_ += step_deg;
    if (angle_deg_ >= 360.0) {
      angle_deg_ -= 360.0;
      revolution_start_ = true;
      new_revolution();
    }
    sample_remainder_ns_ += period_ns;
    const auto whole = static_cast<core::TimeNs>(sample_remainder_ns_);
    next_sample_ns_ += whole;
    sample_remainder_ns_ -= static_cast<double>(whole);
  }
}

void Emulator::emit_sample(double angle_deg, float range_m, bool start) {
  ++stats_.samples;
  const double mm = static_cast<double>(range_m) * 1000.0;
  switch (scan_) {
    case ScanKind::kNone:
      return;
    case ScanKind::kStandard: {
      const double q2 = std::round(mm * 4.0);
      const std::uint16_t dist_q2 = q2 > 0.0 && q2 <= 65535.0 ? static_cast<std::uint16_t>(q2) : 0;
      auto node = proto::encode_standard_node(start, dist_q2 != 0 ? kNodeQuality : 0,
                                              angle_q6(angle_deg), dist_q2);
      emit_frame(node, false);
      return;
    }
    case ScanKind::kExpress:
    case ScanKind::kDense: {
      const bool dense = scan_ == ScanKind::kDense;
      const double limit = dense ? 65535.0 : 16383.0;  // 14-bit express distances
      if (capsule_n_ == 0) capsule_start_deg_ = angle_deg;
      const double r = std::round(mm);
      capsule_mm_[capsule_n_++] = r > 0.0 && r <= limit ? static_cast<std::uint16_t>(r) : 0;
      if (capsule_n_ < (dense ? kDenseSamples : kExpressSamples)) return;
      capsule_n_ = 0;
      const std::uint16_t start_q6 = angle_q6(capsule_start_deg_);
      if (dense) {
        auto c = proto::encode_dense_capsule(start_q6, first_capsule_,
                                             std::span<const std::uint16_t, 40>(capsule_mm_));
        emit_frame(c, true);
      } else {
        // Every sample sits exactly at start + j * step, so the angle corrections are 0.
        std::array<std::uint8_t, proto::kCapsuleSize> c{};
        put_u16(c.data() + 2,
                static_cast<std::uint16_t>((start_q6 & 0x7FFFU) | (first_capsule_ ? 0x8000U : 0U)));
        for (std::size_t cabin = 0; cabin < 16; ++cabin) {
          std::uint8_t* p = c.data() + 4 + 5 * cabin;
          put_u16(p, static_cast<std::uint16_t>(capsule_mm_[2 * cabin] << 2U));
          put_u16(p + 2, static_cast<std::uint16_t>(capsule_mm_[2 * cabin + 1] << 2U));
          p[4] = 0;
        }
        proto::seal_capsule(c);
        emit_frame(c, true);
      }
      first_capsule_ = false;
      return;
    }
  }
}

void Emulator::emit_frame(std::span<std::uint8_t> frame, bool capsule) {
  const EmulatorFaults& f = config_.faults;
  if (f.garbage_probability > 0.0 && uniform() < f.garbage_probability) {
    std::array<std::uint8_t, 16> junk{};
    const std::size_t n = 1 + static_cast<std::size_t>(next_random() % junk.size());
    for (std::size_t k = 0; k < n; ++k) junk[k] = static_cast<std::uint8_t>(next_random());
    put({junk.data(), n});
    ++stats_.garbage_bursts;
  }
  if (f.corrupt_probability > 0.0 && uniform() < f.corrupt_probability) {
    if (capsule) {
      // Inside the checksummed part (after the sync/checksum and angle bytes).
      const std::size_t bit = next_random() % ((frame.size() - 4) * 8);
      frame[4 + bit / 8] = static_cast<std::uint8_t>(frame[4 + bit / 8] ^ (1U << (bit % 8)));
    } else if ((next_random() & 1U) != 0) {
      frame[1] = static_cast<std::uint8_t>(frame[1] ^ 0x01U);  // C check bit
    } else {
      frame[0] = static_cast<std::uint8_t>(frame[0] ^ 0x02U);  // !S no longer inverts S
    }
    ++stats_.corrupted_frames;
  }
  put(frame);
  ++stats_.data_frames;
}

std::span<const std::uint8_t> Emulator::poll(core::TimeNs now_ns) {
  if (returned_ > 0) {
    std::memmove(out_.data(), out_.data() + returned_, out_len_ - returned_);
    out_len_ -= returned_;
    returned_ = 0;
  }
  if (rebooting_until_ns_ != core::kNeverNs && now_ns >= rebooting_until_ns_) {
    rebooting_until_ns_ = core::kNeverNs;
    if (banner_pending_) {
      static constexpr char kBanner[] =
          "RP LIDAR System.\r\nFirmware Ver 1.20 - rc4, HW Ver 5\r\nModel: 28\r\n";
      put({reinterpret_cast<const std::uint8_t*>(kBanner), sizeof kBanner - 1});
      banner_pending_ = false;
    }
  }
  produce(now_ns);
  returned_ = out_len_;
  return {out_.data(), out_len_};
}

}  // namespace coxswain::sim::devices::rplidar
