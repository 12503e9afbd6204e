// SPDX-License-Identifier: Apache-2.0
#include "coxswain/drivers/rplidar/codec.hpp"

#include <algorithm>

namespace coxswain::drivers::rplidar {
namespace {

constexpr int kFullCircleQ6 = 360 << 6;
constexpr int kFullCircleQ8 = 360 << 8;
constexpr int kFullCircleQ16 = 360 << 16;
constexpr std::uint8_t kCapsuleQuality = 0x2F << 2;  // the SDK's fixed capsule quality (188)

std::uint16_t u16_at(const std::uint8_t* p) {
  return static_cast<std::uint16_t>(p[0] | (p[1] << 8));
}
std::uint32_t u32_at(const std::uint8_t* p) {
  return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8U) |
         (static_cast<std::uint32_t>(p[2]) << 16U) | (static_cast<std::uint32_t>(p[3]) << 24U);
}

// Fixed payload size of each known answer type; 0 = unknown/unsupported, SIZE_MAX = variable.
constexpr std::size_t kVariable = static_cast<std::size_t>(-1);
std::size_t answer_size(std::uint8_t type) {
  switch (static_cast<AnswerType>(type)) {
    case AnswerType::kDevInfo:
      return kDevInfoSize;
    case AnswerType::kHealth:
      return kHealthSize;
    case AnswerType::kSampleRate:
      return kSampleRateSize;
    case AnswerType::kLidarConf:
      return kVariable;
    case AnswerType::kMeasurement:
      return kNodeSize;
    case AnswerType::kCapsule:
      return kCapsuleSize;
    case AnswerType::kUltraCapsule:
      return kUltraCapsuleSize;
    case AnswerType::kDenseCapsule:
      return kDenseCapsuleSize;
    case AnswerType::kAccBoardFlag:
      return kAccBoardFlagSize;
    default:
      return 0;
  }
}

bool is_stream_type(std::uint8_t type) {
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

// Wraps a q6 angle into [0, 360) degrees. The SDK adds/subtracts 360 once, which is the same for
// every angle a valid capsule can produce; the full modulo keeps corrupt input in range too.
int wrap_q6(int angle_q6) {
  angle_q6 %= kFullCircleQ6;
  if (angle_q6 < 0) angle_q6 += kFullCircleQ6;
  return angle_q6;
}

std::uint16_t q6_to_z_q14(int angle_q6) {
  return static_cast<std::uint16_t>((wrap_q6(angle_q6) * 256) / 90);
}

int start_angle_q8(const std::uint8_t* capsule) { return (u16_at(capsule + 2) & 0x7FFF) << 2; }

// Angle step between two capsules in q8 degrees (adds 360 when the start angle wrapped).
int diff_q8(int prev_q8, int cur_q8) {
  int d = cur_q8 - prev_q8;
  if (prev_q8 > cur_q8) d += kFullCircleQ8;
  return d;
}

bool crosses_zero(int angle_q16, int inc_q16, int window_q16) {
  return ((angle_q16 + inc_q16) % kFullCircleQ16) < window_q16;
}

HqNode capsule_node(int angle_q6, std::int64_t dist_q2, bool sync) {
  HqNode n;
  n.angle_z_q14 = q6_to_z_q14(angle_q6);
  // The SDK stores a negative ultra prediction as a huge unsigned distance; we call it invalid.
  n.dist_mm_q2 = dist_q2 > 0 ? static_cast<std::uint32_t>(dist_q2) : 0U;
  n.quality = n.dist_mm_q2 != 0 ? kCapsuleQuality : 0;
  n.flag = sync ? 1 : 2;
  return n;
}

}  // namespace

VarBitScale varbitscale_decode(std::uint32_t scaled) {
  // (scaled threshold, target base, level) per docs/protocols.md 1.8.
  struct Row {
    std::uint32_t from;
    std::uint32_t base;
    std::uint32_t level;
  };
  static constexpr std::array<Row, 5> kRows = {
      {{3328, 16384, 4}, {1792, 4096, 3}, {1280, 2048, 2}, {512, 512, 1}, {0, 0, 0}}};
  for (const Row& r : kRows) {
    if (scaled >= r.from) return {r.base + ((scaled - r.from) << r.level), r.level};
  }
  return {};
}

void Decoder::expect(AnswerType type) {
  expected_ = type;
  hunt();
}

void Decoder::expect_any() {
  expected_.reset();
  hunt();
}

void Decoder::reset() { hunt(); }

void Decoder::hunt() {
  phase_ = Phase::kSync1;
  desc_len_ = 0;
  frame_len_ = 0;
  have_prev_ = false;
  in_sync_ = true;
  last_dense_sync_ = 0;
}

std::optional<AnswerType> Decoder::stream_type() const {
  if (phase_ != Phase::kStream) return std::nullopt;
  return static_cast<AnswerType>(answer_type_);
}

DecodeStep Decoder::decode(std::span<const std::uint8_t> bytes) {
  DecodeStep step;
  message_.kind = MessageKind::kNone;
  for (const std::uint8_t b : bytes) {
    ++step.consumed;
    ++stats_.codec.bytes_in;
    if (on_byte(b)) {
      step.produced = true;
      ++stats_.codec.messages_out;
      if (message_.kind == MessageKind::kNodes) stats_.nodes_out += message_.nodes.count;
      break;
    }
  }
  return step;
}

bool Decoder::on_byte(std::uint8_t b) {
  switch (phase_) {
    case Phase::kSync1:
      if (b == kSyncByte1) {
        phase_ = Phase::kSync2;
      } else {
        ++stats_.codec.bytes_skipped;
      }
      return false;
    case Phase::kSync2:
      if (b == kSyncByte2) {
        phase_ = Phase::kDescriptor;
        desc_len_ = 0;
      } else if (b != kSyncByte1) {
        stats_.codec.bytes_skipped += 2;
        phase_ = Phase::kSync1;
      } else {
        ++stats_.codec.bytes_skipped;  // the earlier A5; this one may start the descriptor
      }
      return false;
    case Phase::kDescriptor:
      desc_[desc_len_++] = b;
      if (desc_len_ == desc_.size()) return on_descriptor();
      return false;
    case Phase::kSingle:
      frame_[frame_len_++] = b;
      if (frame_len_ == answer_size_) return on_single_answer();
      return false;
    case Phase::kStream:
      if (answer_type_ == static_cast<std::uint8_t>(AnswerType::kMeasurement)) {
        return on_node_byte(b);
      }
      return on_capsule_byte(b);
  }
  return false;
}

bool Decoder::on_descriptor() {
  const std::uint32_t word = u32_at(desc_.data());
  const std::size_t size = word & 0x3FFFFFFFU;
  const std::uint32_t mode = word >> 30U;
  const std::uint8_t type = desc_[4];
  const std::size_t known = answer_size(type);
  phase_ = Phase::kSync1;
  frame_len_ = 0;
  const bool size_ok = known == kVariable ? (size >= 4 && size <= kMaxConfAnswerSize)
                                          : (known != 0 && size == known);
  const bool mode_ok = is_stream_type(type) ? mode == 1 : mode == 0;
  if (known == 0) {
    // A well-formed descriptor of a kind we do not decode (HQ, ultra-dense, SET_LIDAR_CONF...).
    ++stats_.codec.unsupported;
    stats_.codec.bytes_skipped += kDescriptorSize;
    return false;
  }
  if (!size_ok || !mode_ok) {
    ++stats_.codec.framing_errors;
    stats_.codec.bytes_skipped += kDescriptorSize;
    return false;
  }
  if (expected_ && static_cast<std::uint8_t>(*expected_) != type) {
    ++stats_.unexpected_answers;
    stats_.codec.bytes_skipped += kDescriptorSize;
    return false;
  }
  ++stats_.descriptors;
  answer_type_ = type;
  answer_size_ = size;
  have_prev_ = false;
  in_sync_ = true;
  last_dense_sync_ = 0;
  phase_ = mode == 1 ? Phase::kStream : Phase::kSingle;
  return false;
}

bool Decoder::on_single_answer() {
  phase_ = Phase::kSync1;
  frame_len_ = 0;
  const std::uint8_t* p = frame_.data();
  ++stats_.codec.frames_ok;
  switch (static_cast<AnswerType>(answer_type_)) {
    case AnswerType::kDevInfo: {
      DeviceInfo& d = message_.device_info;
      d.model = p[0];
      d.firmware_minor = p[1];
      d.firmware_major = p[2];
      d.hardware = p[3];
      std::copy(p + 4, p + 20, d.serial.begin());
      message_.kind = MessageKind::kDeviceInfo;
      return true;
    }
    case AnswerType::kHealth:
      message_.health = {p[0], u16_at(p + 1)};
      message_.kind = MessageKind::kHealth;
      return true;
    case AnswerType::kSampleRate:
      message_.sample_rate = {u16_at(p), u16_at(p + 2)};
      message_.kind = MessageKind::kSampleRate;
      return true;
    case AnswerType::kLidarConf: {
      LidarConf& c = message_.lidar_conf;
      c.type = u32_at(p);
      c.size = static_cast<std::uint8_t>(answer_size_ - 4);
      std::fill(c.data.begin(), c.data.end(), std::uint8_t{0});
      std::copy(p + 4, p + answer_size_, c.data.begin());
      message_.kind = MessageKind::kLidarConf;
      return true;
    }
    case AnswerType::kAccBoardFlag:
      message_.acc_board = {u32_at(p)};
      message_.kind = MessageKind::kAccBoardFlag;
      return true;
    default:
      ++stats_.codec.unsupported;
      return false;
  }
}

// Standard nodes (docs/protocols.md 1.6). In sync, a node is accepted when byte 0 has S != !S,
// byte 1 has C = 1 and the angle is below 360 deg (the SDK checks only the first two). These
// checks are weak: structured data can pass them at a wrong byte offset. So after a loss of
// sync the decoder slides one byte at a time and accepts only two consecutive candidates whose
// angle advances by a plausible step (kMinResyncStepQ6..kMaxResyncStepQ6), emitted together.
namespace {
constexpr int kMinResyncStepQ6 = 3;       // > 0.04 deg: a misaligned lock barely moves
constexpr int kMaxResyncStepQ6 = 5 * 64;  // <= 5 deg: no model skips more between samples

bool node_prefix_ok(const std::uint8_t* p, std::size_t len) {
  if (len >= 1 && (((p[0] >> 1U) ^ p[0]) & 1U) == 0) return false;
  if (len >= 2 && (p[1] & 1U) == 0) return false;
  if (len >= 3 && (u16_at(p + 1) >> 1U) >= kFullCircleQ6) return false;
  return true;
}

HqNode node_at(const std::uint8_t* p) {
  return hq_from_standard(p[0], u16_at(p + 1), u16_at(p + 3));
}
}  // namespace

bool Decoder::on_node_byte(std::uint8_t b) {
  frame_[frame_len_++] = b;
  for (;;) {
    bool ok = node_prefix_ok(frame_.data(), std::min(frame_len_, kNodeSize));
    if (ok && !in_sync_ && frame_len_ > kNodeSize) {
      ok = node_prefix_ok(frame_.data() + kNodeSize, frame_len_ - kNodeSize);
      if (ok && frame_len_ == 2 * kNodeSize) {
        const int a1 = u16_at(frame_.data() + 1) >> 1U;
        const int a2 = u16_at(frame_.data() + kNodeSize + 1) >> 1U;
        int step = a2 - a1;
        if (step < 0) step += kFullCircleQ6;
        ok = step >= kMinResyncStepQ6 && step <= kMaxResyncStepQ6;
      }
    }
    if (ok) break;
    if (in_sync_) {
      in_sync_ = false;
      ++stats_.node_check_errors;
      ++stats_.codec.framing_errors;
    }
    ++stats_.codec.bytes_skipped;
    std::copy(frame_.begin() + 1, frame_.begin() + static_cast<std::ptrdiff_t>(frame_len_),
              frame_.begin());
    --frame_len_;
    if (frame_len_ == 0) return false;
  }
  const std::size_t need = in_sync_ ? kNodeSize : 2 * kNodeSize;
  if (frame_len_ < need) return false;
  message_.kind = MessageKind::kNodes;
  message_.nodes.source = AnswerType::kMeasurement;
  message_.nodes.count = static_cast<std::uint32_t>(need / kNodeSize);
  for (std::size_t i = 0; i < message_.nodes.count; ++i) {
    message_.nodes.nodes[i] = node_at(frame_.data() + i * kNodeSize);
  }
  stats_.codec.frames_ok += message_.nodes.count;
  frame_len_ = 0;
  in_sync_ = true;
  return true;
}

void Decoder::lose_capsule_sync() {
  have_prev_ = false;
  if (in_sync_) {
    in_sync_ = false;
    ++stats_.capsule_sync_errors;
    ++stats_.codec.framing_errors;
  }
}

bool Decoder::on_capsule_byte(std::uint8_t b) {
  if (frame_len_ == 0) {
    if ((b >> 4U) != 0xA) {
      lose_capsule_sync();
      ++stats_.codec.bytes_skipped;
      return false;
    }
  } else if (frame_len_ == 1 && (b >> 4U) != 0x5) {
    lose_capsule_sync();
    ++stats_.codec.bytes_skipped;  // the held first byte
    frame_len_ = 0;
    return on_capsule_byte(b);  // this byte may itself be a first byte
  }
  frame_[frame_len_++] = b;
  if (frame_len_ < answer_size_) return false;
  frame_len_ = 0;
  return on_capsule();
}

bool Decoder::on_capsule() {
  std::uint8_t x = 0;
  for (std::size_t i = 2; i < answer_size_; ++i) x = static_cast<std::uint8_t>(x ^ frame_[i]);
  const auto expected =
      static_cast<std::uint8_t>((frame_[0] & 0x0FU) | ((frame_[1] & 0x0FU) << 4U));
  if (x != expected) {
    ++stats_.codec.checksum_errors;
    have_prev_ = false;
    in_sync_ = false;
    return false;
  }
  in_sync_ = true;
  ++stats_.codec.frames_ok;
  if ((frame_[3] & 0x80U) != 0) {
    // S bit: first capsule after start, or rotation was unstable: restart angle decoding.
    ++stats_.capsule_restarts;
    have_prev_ = false;
  }
  bool produced = false;
  if (have_prev_) {
    message_.nodes.source = static_cast<AnswerType>(answer_type_);
    switch (static_cast<AnswerType>(answer_type_)) {
      case AnswerType::kCapsule:
        decode_express();
        produced = true;
        break;
      case AnswerType::kUltraCapsule:
        decode_ultra();
        produced = true;
        break;
      case AnswerType::kDenseCapsule:
        produced = decode_dense();
        break;
      default:
        break;
    }
    if (produced) message_.kind = MessageKind::kNodes;
  }
  std::copy(frame_.begin(), frame_.begin() + static_cast<std::ptrdiff_t>(answer_size_),
            prev_.begin());
  have_prev_ = true;
  return produced;
}

// Express legacy capsule (docs/protocols.md 1.7), the SDK's q16 arithmetic: decodes prev_ using the
// start angle of frame_.
void Decoder::decode_express() {
  const int prev_q8 = start_angle_q8(prev_.data());
  const int inc_q16 = diff_q8(prev_q8, start_angle_q8(frame_.data())) << 3;
  int angle_q16 = prev_q8 << 8;
  std::uint32_t n = 0;
  for (std::size_t cabin = 0; cabin < 16; ++cabin) {
    const std::uint8_t* c = prev_.data() + 4 + 5 * cabin;
    const std::uint16_t d1 = u16_at(c);
    const std::uint16_t d2 = u16_at(c + 2);
    const int offsets[2] = {(c[4] & 0x0F) | ((d1 & 3) << 4), (c[4] >> 4) | ((d2 & 3) << 4)};
    const int dist[2] = {d1 & 0xFFFC, d2 & 0xFFFC};
    for (int k = 0; k < 2; ++k) {
      const int angle_q6 = (angle_q16 - offsets[k] * (1 << 13)) >> 10;
      const bool sync = crosses_zero(angle_q16, inc_q16, inc_q16);
      angle_q16 += inc_q16;
      message_.nodes.nodes[n++] = capsule_node(angle_q6, dist[k], sync);
    }
  }
  message_.nodes.count = n;
}

// Ultra capsule (docs/protocols.md 1.8): 32 cabins x 3 samples, variable-bit-scale distances and a
// distance-dependent angle correction computed exactly as the SDK does (q16 radians -> degrees
// through doubles, truncated).
void Decoder::decode_ultra() {
  const int prev_q8 = start_angle_q8(prev_.data());
  const int inc_q16 = (diff_q8(prev_q8, start_angle_q8(frame_.data())) << 3) / 3;
  int angle_q16 = prev_q8 << 8;
  static const int kOffset75Q16 = static_cast<int>(7.5 * 3.1415926535 * 65536.0 / 180.0);
  static const int kOffset8Q16 = static_cast<int>(8.0 * 3.1415926535 * 65536.0 / 180.0);
  std::uint32_t n = 0;
  for (std::size_t cabin = 0; cabin < 32; ++cabin) {
    const std::uint32_t word = u32_at(prev_.data() + 4 + 4 * cabin);
    const std::uint32_t next_word =
        cabin == 31 ? u32_at(frame_.data() + 4) : u32_at(prev_.data() + 4 + 4 * (cabin + 1));
    // Sign-extend the two 10-bit predictions.
    const int predict1 =
        static_cast<int>((word >> 12U) & 0x3FFU) - ((word & (1U << 21U)) ? 1024 : 0);
    const int predict2 = static_cast<int>(word >> 22U) - ((word & (1U << 31U)) ? 1024 : 0);
    const VarBitScale m1 = varbitscale_decode(word & 0xFFFU);
    const VarBitScale m2 = varbitscale_decode(next_word & 0xFFFU);
    const auto major1 = static_cast<std::int64_t>(m1.value_mm);
    const auto major2 = static_cast<std::int64_t>(m2.value_mm);
    std::int64_t base1 = major1;
    std::uint32_t level1 = m1.level;
    if (major1 == 0 && major2 != 0) {
      base1 = major2;
      level1 = m2.level;
    }
    std::int64_t dist_q2[3];
    dist_q2[0] = major1 * 4;
    dist_q2[1] = (predict1 == -512 || predict1 == 511)
                     ? 0
                     : (predict1 * (std::int64_t{1} << level1) + base1) * 4;
    dist_q2[2] = (predict2 == -512 || predict2 == 511)
                     ? 0
                     : (predict2 * (std::int64_t{1} << m2.level) + major2) * 4;
    for (const std::int64_t d : dist_q2) {
      const bool sync = crosses_zero(angle_q16, inc_q16, inc_q16);
      int offset_q16 = kOffset75Q16;
      if (d >= 50 * 4) {
        const int k2 = static_cast<int>(98361 / d);
        offset_q16 = kOffset8Q16 - (k2 << 6) - (k2 * k2 * k2) / 98304;
      }
      const int offset_deg_q16 =
          static_cast<int>(static_cast<double>(offset_q16 * 180) / 3.14159265);
      const int angle_q6 = (angle_q16 - offset_deg_q16) >> 10;
      angle_q16 += inc_q16;
      message_.nodes.nodes[n++] = capsule_node(angle_q6, d, sync);
    }
  }
  message_.nodes.count = n;
}

// Dense capsule (docs/protocols.md 1.9): 40 plain distances, angles interpolated, no correction.
bool Decoder::decode_dense() {
  const int prev_q8 = start_angle_q8(prev_.data());
  const int step_q8 = diff_q8(prev_q8, start_angle_q8(frame_.data()));
  if (config_.dense_sample_duration_us != 0) {
    // Largest step a 100 Hz rotation could make in 40 samples.
    const double max_step_deg =
        360.0 * 100.0 * 40.0 * static_cast<double>(config_.dense_sample_duration_us) / 1e6;
    if (static_cast<double>(step_q8) / 256.0 > max_step_deg) {
      ++stats_.dense_rejected;
      return false;
    }
  }
  const int inc_q16 = (step_q8 << 8) / 40;
  int angle_q16 = prev_q8 << 8;
  for (std::size_t k = 0; k < 40; ++k) {
    const std::uint16_t dist_mm = u16_at(prev_.data() + 4 + 2 * k);
    int sync = crosses_zero(angle_q16, inc_q16, inc_q16 * 2) ? 1 : 0;
    sync = (sync ^ last_dense_sync_) & sync;  // the SDK flags only the first of two
    last_dense_sync_ = sync;
    message_.nodes.nodes[k] = capsule_node(angle_q16 >> 10, std::int64_t{dist_mm} * 4, sync != 0);
    angle_q16 += inc_q16;
  }
  message_.nodes.count = 40;
  return true;
}

}  // namespace coxswain::drivers::rplidar
