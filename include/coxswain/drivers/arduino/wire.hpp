// SPDX-License-Identifier: Apache-2.0
#pragma once
// NUC <-> Arduino Mega wire protocol, shared verbatim by the daemon (C++20) and the firmware
// (avr-gcc 5, -std=gnu++11). Specification: tools/arduino/PROTOCOL.md.
//
// Portability rules for this file (it is compiled by both compilers, see tools/arduino/build.sh):
// C++11 only, <stdint.h>/<stddef.h>/<string.h> only, no STL, no exceptions, no dynamic memory,
// no virtual functions, no floating point, `int` may be 16 bits.
//
// Frame: A5 5A | len | type | seq_lo seq_hi | payload[len] | crc_lo crc_hi
// CRC-16/CCITT-FALSE (poly 0x1021, init 0xFFFF, no reflection, xorout 0) over len..payload.
// All multi-byte fields little-endian.
#include <stddef.h>  // NOLINT(modernize-deprecated-headers): avr-libc has no <cstddef>
#include <stdint.h>  // NOLINT(modernize-deprecated-headers)
#include <string.h>  // NOLINT(modernize-deprecated-headers)

// Nested namespace definitions are C++17; the firmware compiler is C++11.
namespace coxswain {  // NOLINT(modernize-concat-nested-namespaces)
namespace drivers {
namespace arduino {

const uint8_t kSync0 = 0xA5;
const uint8_t kSync1 = 0x5A;
const uint8_t kProtocolVersion = 1;
const uint8_t kHeaderBytes = 6;  // sync0 sync1 len type seq(2)
const uint8_t kCrcBytes = 2;
const uint8_t kMaxPayload = 48;
const uint8_t kMaxFrame = kHeaderBytes + kMaxPayload + kCrcBytes;
const uint8_t kChannels = 2;    // output channels (Timer1 OC1A / OC1B)
const uint8_t kRcChannels = 3;  // RC receiver inputs: steering, throttle, mode switch

/// Message types. Host -> board below 0x80, board -> host from 0x80.
enum class MsgType : uint8_t {
  kHello = 0x01,       // host (re)connected: board answers Ready, forgets the sequence
  kPing = 0x02,        // board answers Pong with the same token
  kSetOutputs = 0x10,  // actuator command
  kReady = 0x81,       // board booted (or answered Hello)
  kPong = 0x82,
  kTelemetry = 0x83,
};

/// SetOutputs.flags bits.
const uint8_t kFlagArm = 0x01;  // clear = host wants neutral outputs (hold, finished, shutdown)

/// Telemetry.flags bits.
const uint8_t kTelEstop = 0x01;
const uint8_t kTelRcPresent = 0x02;
const uint8_t kTelFailsafe = 0x04;  // no fresh host command: host outputs are not applied
const uint8_t kTelStartSwitch = 0x08;
const uint8_t kTelArmed = 0x10;     // last fresh host command had kFlagArm
const uint8_t kTelBootHold = 0x20;  // ESC arming hold after reset: outputs neutral

/// Mode as decided from the RC mode switch (autonomous only with RC present and no e-stop).
enum class Mode : uint8_t { kManual = 0, kAutonomous = 1 };

/// Who decided the applied pulses (Telemetry.source), for diagnosis.
enum class OutputSource : uint8_t {
  kBootHold = 0,
  kEstop = 1,
  kNoRc = 2,
  kRcManual = 3,
  kHost = 4,
  kFailsafe = 5,
  kDisarmed = 6,
};

// Payload sizes (bytes). Frames of a known type with another length are malformed.
const uint8_t kHelloPayload = 1;
const uint8_t kPingPayload = 4;
const uint8_t kSetOutputsPayload = 6;
const uint8_t kReadyPayload = 12;
const uint8_t kPongPayload = 8;
const uint8_t kTelemetryPayload = 36;

struct Hello {
  uint8_t protocol_version;
};

struct Ping {
  uint32_t token;
};

/// Host -> board actuator command. led uses msg::LedColour numbering (0 off .. 6 white).
struct SetOutputs {
  uint16_t pulse_us[kChannels];
  uint8_t led;
  uint8_t flags;
};

struct Ready {
  uint8_t protocol_version;
  uint8_t fw_major;
  uint8_t fw_minor;
  uint8_t fw_patch;
  uint16_t failsafe_ms;
  uint16_t neutral_us[kChannels];
  uint8_t reset_cause;  // AVR MCUSR at boot (bit0 power-on, 1 external, 2 brown-out, 3 watchdog)
  uint8_t rc_channels;
};

struct Pong {
  uint32_t token;
  uint32_t uptime_ms;
};

/// Board -> host status, sent at ~20 Hz. Counters are 16-bit and wrap.
struct Telemetry {
  uint32_t uptime_ms;
  uint16_t applied_pulse_us[kChannels];
  uint16_t rc_pulse_us[kRcChannels];  // last valid pulse per RC channel, 0 = none fresh
  uint8_t led;
  uint8_t mode;    // Mode
  uint8_t flags;   // kTel* bits
  uint8_t source;  // OutputSource
  uint16_t supply_mv;
  uint16_t last_seq;  // sequence of the last accepted SetOutputs
  uint16_t rx_frames_ok;
  uint16_t rx_crc_errors;
  uint16_t rx_framing_errors;
  uint16_t rx_bytes_skipped;
  uint16_t seq_gaps;        // SetOutputs missed (sequence jumps)
  uint16_t seq_duplicates;  // SetOutputs ignored because their sequence repeated
  uint16_t failsafe_events;
};

// ---------------------------------------------------------------------------------------------
// CRC-16/CCITT-FALSE, bitwise: no 512-byte table in the AVR's 8 KiB of RAM.
// Check value: crc16_ccitt_false("123456789") == 0x29B1.
inline uint16_t crc16_update(uint16_t crc, uint8_t byte) {
  crc = static_cast<uint16_t>(crc ^ static_cast<uint16_t>(static_cast<uint16_t>(byte) << 8U));
  for (uint8_t bit = 0; bit < 8; ++bit) {
    if ((crc & 0x8000U) != 0U) {
      crc = static_cast<uint16_t>(static_cast<uint16_t>(crc << 1U) ^ 0x1021U);
    } else {
      crc = static_cast<uint16_t>(crc << 1U);
    }
  }
  return crc;
}

inline uint16_t crc16_ccitt_false(const uint8_t* data, size_t size) {
  uint16_t crc = 0xFFFF;
  for (size_t i = 0; i < size; ++i) {
    crc = crc16_update(crc, data[i]);
  }
  return crc;
}

// ---------------------------------------------------------------------------------------------
// Little-endian field helpers.
inline void put_u16(uint8_t* p, uint16_t v) {
  p[0] = static_cast<uint8_t>(v & 0xFFU);
  p[1] = static_cast<uint8_t>(v >> 8U);
}
inline void put_u32(uint8_t* p, uint32_t v) {
  p[0] = static_cast<uint8_t>(v & 0xFFUL);
  p[1] = static_cast<uint8_t>((v >> 8U) & 0xFFUL);
  p[2] = static_cast<uint8_t>((v >> 16U) & 0xFFUL);
  p[3] = static_cast<uint8_t>(v >> 24U);
}
inline uint16_t get_u16(const uint8_t* p) {
  return static_cast<uint16_t>(static_cast<uint16_t>(p[0]) |
                               static_cast<uint16_t>(static_cast<uint16_t>(p[1]) << 8U));
}
inline uint32_t get_u32(const uint8_t* p) {
  return static_cast<uint32_t>(p[0]) | (static_cast<uint32_t>(p[1]) << 8U) |
         (static_cast<uint32_t>(p[2]) << 16U) | (static_cast<uint32_t>(p[3]) << 24U);
}

// ---------------------------------------------------------------------------------------------
// Encoding. Each returns the frame size written to `out`, or 0 when `capacity` is too small or
// the payload too long. kMaxFrame bytes always suffice.
inline size_t encode_frame(MsgType type, uint16_t seq, const uint8_t* payload, uint8_t len,
                           uint8_t* out, size_t capacity) {
  const size_t total = static_cast<size_t>(kHeaderBytes) + len + kCrcBytes;
  if (len > kMaxPayload || capacity < total || out == NULL) {  // NOLINT(modernize-use-nullptr)
    return 0;
  }
  out[0] = kSync0;
  out[1] = kSync1;
  out[2] = len;
  out[3] = static_cast<uint8_t>(type);
  put_u16(out + 4, seq);
  if (len > 0) {
    memcpy(out + kHeaderBytes, payload, len);
  }
  const uint16_t crc = crc16_ccitt_false(out + 2, static_cast<size_t>(len) + 4U);
  put_u16(out + kHeaderBytes + len, crc);
  return total;
}

inline size_t encode(const Hello& m, uint16_t seq, uint8_t* out, size_t capacity) {
  uint8_t p[kHelloPayload];
  p[0] = m.protocol_version;
  return encode_frame(MsgType::kHello, seq, p, kHelloPayload, out, capacity);
}

inline size_t encode(const Ping& m, uint16_t seq, uint8_t* out, size_t capacity) {
  uint8_t p[kPingPayload];
  put_u32(p, m.token);
  return encode_frame(MsgType::kPing, seq, p, kPingPayload, out, capacity);
}

inline size_t encode(const SetOutputs& m, uint16_t seq, uint8_t* out, size_t capacity) {
  uint8_t p[kSetOutputsPayload];
  put_u16(p + 0, m.pulse_us[0]);
  put_u16(p + 2, m.pulse_us[1]);
  p[4] = m.led;
  p[5] = m.flags;
  return encode_frame(MsgType::kSetOutputs, seq, p, kSetOutputsPayload, out, capacity);
}

inline size_t encode(const Ready& m, uint16_t seq, uint8_t* out, size_t capacity) {
  uint8_t p[kReadyPayload];
  p[0] = m.protocol_version;
  p[1] = m.fw_major;
  p[2] = m.fw_minor;
  p[3] = m.fw_patch;
  put_u16(p + 4, m.failsafe_ms);
  put_u16(p + 6, m.neutral_us[0]);
  put_u16(p + 8, m.neutral_us[1]);
  p[10] = m.reset_cause;
  p[11] = m.rc_channels;
  return encode_frame(MsgType::kReady, seq, p, kReadyPayload, out, capacity);
}

inline size_t encode(const Pong& m, uint16_t seq, uint8_t* out, size_t capacity) {
  uint8_t p[kPongPayload];
  put_u32(p + 0, m.token);
  put_u32(p + 4, m.uptime_ms);
  return encode_frame(MsgType::kPong, seq, p, kPongPayload, out, capacity);
}

inline size_t encode(const Telemetry& m, uint16_t seq, uint8_t* out, size_t capacity) {
  uint8_t p[kTelemetryPayload];
  put_u32(p + 0, m.uptime_ms);
  put_u16(p + 4, m.applied_pulse_us[0]);
  put_u16(p + 6, m.applied_pulse_us[1]);
  put_u16(p + 8, m.rc_pulse_us[0]);
  put_u16(p + 10, m.rc_pulse_us[1]);
  put_u16(p + 12, m.rc_pulse_us[2]);
  p[14] = m.led;
  p[15] = m.mode;
  p[16] = m.flags;
  p[17] = m.source;
  put_u16(p + 18, m.supply_mv);
  put_u16(p + 20, m.last_seq);
  put_u16(p + 22, m.rx_frames_ok);
  put_u16(p + 24, m.rx_crc_errors);
  put_u16(p + 26, m.rx_framing_errors);
  put_u16(p + 28, m.rx_bytes_skipped);
  put_u16(p + 30, m.seq_gaps);
  put_u16(p + 32, m.seq_duplicates);
  put_u16(p + 34, m.failsafe_events);
  return encode_frame(MsgType::kTelemetry, seq, p, kTelemetryPayload, out, capacity);
}

// ---------------------------------------------------------------------------------------------
// Decoding.

/// One checksummed frame as received. `payload` points into the decoder and stays valid until
/// the decoder is called again.
struct Frame {
  uint8_t type;  // raw MsgType value (unknown types are delivered too; the caller counts them)
  uint16_t seq;
  uint8_t len;
  const uint8_t* payload;
};

inline bool parse(const Frame& f, Hello* out) {
  if (f.type != static_cast<uint8_t>(MsgType::kHello) || f.len != kHelloPayload) {
    return false;
  }
  out->protocol_version = f.payload[0];
  return true;
}

inline bool parse(const Frame& f, Ping* out) {
  if (f.type != static_cast<uint8_t>(MsgType::kPing) || f.len != kPingPayload) {
    return false;
  }
  out->token = get_u32(f.payload);
  return true;
}

inline bool parse(const Frame& f, SetOutputs* out) {
  if (f.type != static_cast<uint8_t>(MsgType::kSetOutputs) || f.len != kSetOutputsPayload) {
    return false;
  }
  out->pulse_us[0] = get_u16(f.payload + 0);
  out->pulse_us[1] = get_u16(f.payload + 2);
  out->led = f.payload[4];
  out->flags = f.payload[5];
  return true;
}

inline bool parse(const Frame& f, Ready* out) {
  if (f.type != static_cast<uint8_t>(MsgType::kReady) || f.len != kReadyPayload) {
    return false;
  }
  const uint8_t* p = f.payload;
  out->protocol_version = p[0];
  out->fw_major = p[1];
  out->fw_minor = p[2];
  out->fw_patch = p[3];
  out->failsafe_ms = get_u16(p + 4);
  out->neutral_us[0] = get_u16(p + 6);
  out->neutral_us[1] = get_u16(p + 8);
  out->reset_cause = p[10];
  out->rc_channels = p[11];
  return true;
}

inline bool parse(const Frame& f, Pong* out) {
  if (f.type != static_cast<uint8_t>(MsgType::kPong) || f.len != kPongPayload) {
    return false;
  }
  out->token = get_u32(f.payload);
  out->uptime_ms = get_u32(f.payload + 4);
  return true;
}

inline bool parse(const Frame& f, Telemetry* out) {
  if (f.type != static_cast<uint8_t>(MsgType::kTelemetry) || f.len != kTelemetryPayload) {
    return false;
  }
  const uint8_t* p = f.payload;
  out->uptime_ms = get_u32(p + 0);
  out->applied_pulse_us[0] = get_u16(p + 4);
  out->applied_pulse_us[1] = get_u16(p + 6);
  out->rc_pulse_us[0] = get_u16(p + 8);
  out->rc_pulse_us[1] = get_u16(p + 10);
  out->rc_pulse_us[2] = get_u16(p + 12);
  out->led = p[14];
  out->mode = p[15];
  out->flags = p[16];
  out->source = p[17];
  out->supply_mv = get_u16(p + 18);
  out->last_seq = get_u16(p + 20);
  out->rx_frames_ok = get_u16(p + 22);
  out->rx_crc_errors = get_u16(p + 24);
  out->rx_framing_errors = get_u16(p + 26);
  out->rx_bytes_skipped = get_u16(p + 28);
  out->seq_gaps = get_u16(p + 30);
  out->seq_duplicates = get_u16(p + 32);
  out->failsafe_events = get_u16(p + 34);
  return true;
}

/// Traffic and error counters of a FrameDecoder (32-bit: they wrap after 4 GiB).
struct DecoderStats {
  uint32_t bytes_in;
  uint32_t frames_ok;       // CRC-valid frames delivered
  uint32_t crc_errors;      // candidate frames whose CRC failed
  uint32_t framing_errors;  // sync found but impossible length
  uint32_t bytes_skipped;   // bytes dropped while hunting for a frame start
};

/// Incremental frame decoder: bytes may arrive split anywhere and mixed with garbage. After a
/// CRC failure it resynchronises on the byte after the false sync, so a valid frame hidden
/// inside a corrupted one is still found. Fixed buffer of kMaxFrame bytes, no allocation.
/// Not thread-safe (one instance per serial link).
class FrameDecoder {
 public:
  FrameDecoder() : n_(0), pending_drop_(0) { reset(); }

  void reset() {
    n_ = 0;
    pending_drop_ = 0;
    memset(&stats_, 0, sizeof(stats_));
    memset(&frame_, 0, sizeof(frame_));
    frame_.payload = buf_;
  }

  /// Consumes bytes until one frame completes (then *produced = true and frame() is valid) or the
  /// input ends. Returns the bytes consumed: >= 1 when size > 0. With size == 0 it only delivers a
  /// frame still held back after a resync; callers call it at end of input until it produces
  /// nothing.
  size_t decode(const uint8_t* data, size_t size, bool* produced) {
    *produced = false;
    drop_delivered();
    if (size == 0) {
      *produced = parse_buffer();
      return 0;
    }
    for (size_t i = 0; i < size; ++i) {
      buf_[n_++] = data[i];  // n_ < kMaxFrame holds before every append (see parse_buffer)
      ++stats_.bytes_in;
      if (parse_buffer()) {
        *produced = true;
        return i + 1;
      }
    }
    return size;
  }

  /// Firmware convenience: one byte in, true when frame() holds a new frame.
  bool push(uint8_t byte) {
    bool produced = false;
    (void)decode(&byte, 1, &produced);
    return produced;
  }

  const Frame& frame() const { return frame_; }
  const DecoderStats& stats() const { return stats_; }

 private:
  void drop_delivered() {
    if (pending_drop_ > 0) {
      remove_front(pending_drop_);
      pending_drop_ = 0;
    }
  }

  void remove_front(uint8_t k) {
    if (k >= n_) {
      n_ = 0;
      return;
    }
    memmove(buf_, buf_ + k, static_cast<size_t>(n_ - k));
    n_ = static_cast<uint8_t>(n_ - k);
  }

  // Drops the first byte and everything up to the next possible sync byte.
  void skip_to_next_sync() {
    uint8_t k = 1;
    while (k < n_ && buf_[k] != kSync0) {
      ++k;
    }
    stats_.bytes_skipped += k;
    remove_front(k);
  }

  // Looks for a complete frame at the start of the buffer, dropping garbage in front of it.
  // Leaves either a delivered frame (returns true) or an incomplete candidate shorter than its
  // declared size (so n_ < kMaxFrame afterwards).
  bool parse_buffer() {
    for (;;) {
      if (n_ == 0) {
        return false;
      }
      if (buf_[0] != kSync0) {
        skip_to_next_sync();
        continue;
      }
      if (n_ < 2) {
        return false;
      }
      if (buf_[1] != kSync1) {
        skip_to_next_sync();
        continue;
      }
      if (n_ < 3) {
        return false;
      }
      const uint8_t len = buf_[2];
      if (len > kMaxPayload) {
        ++stats_.framing_errors;
        skip_to_next_sync();
        continue;
      }
      const uint8_t need = static_cast<uint8_t>(kHeaderBytes + len + kCrcBytes);
      if (n_ < need) {
        return false;
      }
      const uint16_t crc = crc16_ccitt_false(buf_ + 2, static_cast<size_t>(len) + 4U);
      if (crc != get_u16(buf_ + kHeaderBytes + len)) {
        ++stats_.crc_errors;
        skip_to_next_sync();
        continue;
      }
      ++stats_.frames_ok;
      frame_.type = buf_[3];
      frame_.seq = get_u16(buf_ + 4);
      frame_.len = len;
      frame_.payload = buf_ + kHeaderBytes;
      pending_drop_ = need;
      return true;
    }
  }

  uint8_t buf_[kMaxFrame]{};
  uint8_t n_;
  uint8_t pending_drop_;
  Frame frame_{};
  DecoderStats stats_{};
};

}  // namespace arduino
}  // namespace drivers
}  // namespace coxswain
