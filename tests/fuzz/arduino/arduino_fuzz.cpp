// SPDX-License-Identifier: Apache-2.0
// libFuzzer target: the portable FrameDecoder (as the firmware and daemon run it), the host
// ArduinoCodec, and the firmware decision core fed by the decoded frames. Checks invariants:
// consumed >= 1 per non-empty call, every delivered frame re-encodes to identical bytes,
// statistics add up, outputs are always within limits and neutral whenever safety demands it.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <span>

#include "coxswain/drivers/arduino/codec.hpp"
#include "coxswain/drivers/arduino/firmware_logic.hpp"
#include "coxswain/drivers/arduino/wire.hpp"

namespace cx = coxswain::drivers::arduino;

namespace {

void check(bool ok) {
  if (!ok) std::abort();
}

template <typename M>
void check_reencode(const cx::Frame& f) {
  M m{};
  if (!cx::parse(f, &m)) return;
  std::uint8_t buf[cx::kMaxFrame];
  const std::size_t n = cx::encode(m, f.seq, buf, sizeof(buf));
  check(n == static_cast<std::size_t>(cx::kHeaderBytes) + f.len + cx::kCrcBytes);
  check(std::memcmp(buf + cx::kHeaderBytes, f.payload, f.len) == 0);
}

void check_outputs(const cx::LogicConfig& c, const cx::LogicOutputs& o, bool estop) {
  for (std::uint8_t ch = 0; ch < cx::kChannels; ++ch) {
    check(o.pulse_us[ch] >= c.min_us[ch] && o.pulse_us[ch] <= c.max_us[ch]);
  }
  const bool neutral_required = o.boot_hold || estop || !o.rc_present;
  if (neutral_required || o.source == cx::OutputSource::kFailsafe ||
      o.source == cx::OutputSource::kDisarmed) {
    check(o.pulse_us[0] == c.neutral_us[0] && o.pulse_us[1] == c.neutral_us[1]);
  }
  if (o.mode == cx::Mode::kAutonomous) check(o.rc_present && !estop);
  if (o.source == cx::OutputSource::kHost) check(!o.failsafe && o.armed);
}

// Structured mode: 8-byte records build a valid host stream (SetOutputs, Hello, RC pulses,
// e-stop, line noise, time steps), which is decoded and drives the firmware core, so the logic
// sees deep sequences that random bytes rarely reach through the CRC.
void run_structured(const std::uint8_t* data, std::size_t size) {
  cx::LogicConfig cfg;
  cx::FirmwareLogic logic(cfg);
  std::uint32_t now_ms = 0xFFFFF000U;  // cross the millis() wrap
  logic.reset(now_ms);
  cx::FrameDecoder d;
  std::uint16_t seq = 0;
  bool estop = false;
  std::uint32_t accepted = 0;
  for (std::size_t i = 0; i + 8 <= size; i += 8) {
    const std::uint8_t* r = data + i;
    const std::uint16_t a = static_cast<std::uint16_t>(r[1] | (r[2] << 8));
    const std::uint16_t b = static_cast<std::uint16_t>(r[3] | (r[4] << 8));
    now_ms += static_cast<std::uint32_t>(r[7]) * 4U;
    std::uint8_t frame[cx::kMaxFrame];
    std::size_t n = 0;
    switch (r[0] % 6) {
      case 0:
      case 1: {
        if (r[0] % 6 == 0) ++seq;  // case 1 repeats the sequence
        const cx::SetOutputs so{{a, b}, r[5], r[6]};
        n = cx::encode(so, seq, frame, sizeof(frame));
        break;
      }
      case 2:
        n = cx::encode(cx::Hello{1}, seq, frame, sizeof(frame));
        break;
      case 3:
        logic.on_rc_pulse(now_ms, static_cast<std::uint8_t>(r[5] % 4), a);
        logic.on_rc_pulse(now_ms, static_cast<std::uint8_t>(r[6] % 4), b);
        break;
      case 4:
        estop = (r[5] & 1U) != 0;
        break;
      default:
        frame[0] = r[5];  // noise byte
        n = 1;
        break;
    }
    for (std::size_t k = 0; k < n; ++k) {
      if (!d.push(frame[k])) continue;
      const cx::Frame& f = d.frame();
      cx::SetOutputs so{};
      if (cx::parse(f, &so)) {
        accepted += logic.on_set_outputs(now_ms, f.seq, so) ? 1U : 0U;
      } else if (f.type == static_cast<std::uint8_t>(cx::MsgType::kHello)) {
        logic.on_hello();
      }
    }
    const cx::LogicOutputs o = logic.step(now_ms, cx::SwitchInputs{estop, false});
    check_outputs(cfg, o, estop);
  }
  check(logic.counters().commands_accepted == static_cast<std::uint16_t>(accepted));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > 0 && data[0] == 0xC5) {
    run_structured(data + 1, size - 1);
    return 0;
  }
  // 1. Portable decoder + firmware core, chunked by the first byte of input.
  cx::LogicConfig cfg;
  cfg.boot_neutral_ms = 100;
  cx::FirmwareLogic logic(cfg);
  logic.reset(0);
  cx::FrameDecoder d;
  const std::size_t chunk = size > 0 ? (data[0] % 17U) + 1U : 1U;
  std::uint32_t now_ms = 0;
  std::size_t pos = 0;
  std::uint32_t frames = 0;
  while (pos < size) {
    const std::size_t len = size - pos < chunk ? size - pos : chunk;
    bool produced = false;
    const std::size_t used = d.decode(data + pos, len, &produced);
    check(used >= 1 && used <= len);
    pos += used;
    now_ms += static_cast<std::uint32_t>(used) * 3U;  // time advances with the bytes
    if (produced) {
      ++frames;
      const cx::Frame& f = d.frame();
      check_reencode<cx::Hello>(f);
      check_reencode<cx::Ping>(f);
      check_reencode<cx::SetOutputs>(f);
      check_reencode<cx::Ready>(f);
      check_reencode<cx::Pong>(f);
      check_reencode<cx::Telemetry>(f);
      cx::SetOutputs so{};
      if (cx::parse(f, &so)) (void)logic.on_set_outputs(now_ms, f.seq, so);
      // Treat a Telemetry frame's RC fields as RC input, and its flags as the e-stop pin.
      cx::Telemetry tel{};
      bool estop = false;
      if (cx::parse(f, &tel)) {
        for (std::uint8_t ch = 0; ch < cx::kRcChannels; ++ch) {
          logic.on_rc_pulse(now_ms, ch, tel.rc_pulse_us[ch]);
        }
        estop = (tel.flags & cx::kTelEstop) != 0;
      }
      if (f.type == static_cast<std::uint8_t>(cx::MsgType::kHello)) logic.on_hello();
      const cx::LogicOutputs o = logic.step(now_ms, cx::SwitchInputs{estop, false});
      check_outputs(cfg, o, estop);
    }
  }
  bool produced = true;
  while (produced) {
    (void)d.decode(nullptr, 0, &produced);
    if (produced) ++frames;
  }
  const cx::DecoderStats& st = d.stats();
  check(st.bytes_in == size);
  check(st.frames_ok == frames);
  check(st.bytes_skipped <= size);

  // 2. Host codec on the same bytes.
  cx::ArduinoCodec codec;
  std::span<const std::uint8_t> rest(data, size);
  while (!rest.empty()) {
    const coxswain::drivers::DecodeStep step = codec.decode(rest);
    check(step.consumed >= 1 && step.consumed <= rest.size());
    rest = rest.subspan(step.consumed);
    if (step.produced && codec.message().type == cx::MsgType::kTelemetry) {
      (void)cx::to_status(codec.message().telemetry, 0);
    }
  }
  while (codec.decode({}).produced) {
  }
  const coxswain::drivers::CodecStats cs = codec.stats();
  check(cs.frames_ok == frames);
  check(cs.messages_out + cs.unsupported <= cs.frames_ok);
  return 0;
}
