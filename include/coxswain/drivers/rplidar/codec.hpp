// SPDX-License-Identifier: Apache-2.0
#pragma once
// RPLIDAR response decoder (lidar -> host). Protocol: docs/protocols.md section 1 (1.4-1.9, 1.12).
// Follows the codec convention of coxswain/drivers/codec.hpp: pure, bytes in, at most one message
// per decode() call, fixed buffers, no allocation, no clock.
//
// Byte-level state machine: hunt `A5 5A` -> 4-byte length/mode -> answer type. Single answers
// (DEVINFO, HEALTH, SAMPLERATE, LIDAR_CONF, ACC_BOARD_FLAG) are decoded once; continuous answers
// (standard nodes 0x81, express capsules 0x82, ultra capsules 0x84, dense capsules 0x85) are cut
// back to back until reset()/expect() (the caller sends STOP/RESET or a new command).
// Measurements come out in the SDK's HQ-node form with the SDK's integer arithmetic, so the
// recorded pyrplidar vectors match bit for bit (dtheta is unsigned and subtracted, per the SDK,
// not the manual's sign bit: docs/protocols.md 1.7 [conflict]).
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>

#include "coxswain/drivers/codec.hpp"
#include "coxswain/drivers/rplidar/protocol.hpp"

namespace coxswain::drivers::rplidar {

/// Nodes decoded from one standard node (1) or one capsule (32 / 96 / 40).
struct NodeBatch {
  static constexpr std::size_t kMaxNodes = 96;
  AnswerType source = AnswerType::kMeasurement;
  std::uint32_t count = 0;
  std::array<HqNode, kMaxNodes> nodes{};

  [[nodiscard]] std::span<const HqNode> span() const { return {nodes.data(), count}; }
};

enum class MessageKind : std::uint8_t {
  kNone,
  kDeviceInfo,
  kHealth,
  kSampleRate,
  kLidarConf,
  kAccBoardFlag,
  kNodes,
};

/// The decoder's last output; only the member named by `kind` is meaningful.
struct Message {
  MessageKind kind = MessageKind::kNone;
  DeviceInfo device_info;
  Health health;
  SampleRate sample_rate;
  LidarConf lidar_conf;
  AccBoardFlag acc_board;
  NodeBatch nodes;
};

/// CodecStats plus the RPLIDAR-specific error kinds.
struct DecoderStats {
  CodecStats codec;
  std::uint64_t descriptors = 0;          // valid response descriptors seen
  std::uint64_t unexpected_answers = 0;   // descriptors of another type than expect()ed
  std::uint64_t node_check_errors = 0;    // 0x81 S/!S, C-bit or angle check lost sync
  std::uint64_t capsule_sync_errors = 0;  // capsule sync nibbles lost
  std::uint64_t capsule_restarts = 0;     // capsules with the S (restart) bit
  std::uint64_t dense_rejected = 0;       // dense capsule pairs with an impossible angle step
  std::uint64_t nodes_out = 0;            // HQ nodes produced
};

struct DecoderConfig {
  /// Dense capsules: the SDK drops a capsule pair whose angle step exceeds what a 100 Hz rotation
  /// could produce at this sample duration (µs, from SCAN_MODE_US_PER_SAMPLE). 0 = no check.
  std::uint32_t dense_sample_duration_us = 0;
};

/// Stateful RPLIDAR answer decoder. Not thread-safe (one owner: the lidar adapter).
/// Holds about 1.5 kB; never allocates.
class Decoder {
 public:
  explicit Decoder(DecoderConfig config = {}) : config_(config) {}

  /// After sending a command: accept only a descriptor of `type`; anything else is counted as
  /// unexpected and skipped. Also forgets any stream and capsule state.
  void expect(AnswerType type);
  /// Accept any descriptor (e.g. when attaching to a lidar that is already streaming after a
  /// SCAN sent by someone else). Forgets stream and capsule state.
  void expect_any();
  /// Forget partial frames, stream mode and capsule state (after STOP/RESET); keeps the
  /// expectation and the statistics.
  void reset();
  void set_dense_sample_duration_us(std::uint32_t us) { config_.dense_sample_duration_us = us; }

  [[nodiscard]] DecodeStep decode(std::span<const std::uint8_t> bytes);
  [[nodiscard]] const Message& message() const { return message_; }
  [[nodiscard]] const DecoderStats& stats() const { return stats_; }
  /// Type of the continuous answer being cut, if the decoder is inside one.
  [[nodiscard]] std::optional<AnswerType> stream_type() const;

 private:
  enum class Phase : std::uint8_t { kSync1, kSync2, kDescriptor, kSingle, kStream };
  static constexpr std::size_t kMaxFrame = 132;

  bool on_byte(std::uint8_t b);  // true when message_ was produced
  bool on_descriptor();
  bool on_single_answer();
  bool on_node_byte(std::uint8_t b);
  bool on_capsule_byte(std::uint8_t b);
  bool on_capsule();
  void decode_express();
  void decode_ultra();
  bool decode_dense();
  void lose_capsule_sync();
  void hunt();

  DecoderConfig config_;
  std::optional<AnswerType> expected_;
  Phase phase_ = Phase::kSync1;
  std::array<std::uint8_t, 5> desc_{};
  std::size_t desc_len_ = 0;
  std::uint8_t answer_type_ = 0;
  std::size_t answer_size_ = 0;
  std::array<std::uint8_t, kMaxFrame> frame_{};
  std::size_t frame_len_ = 0;
  std::array<std::uint8_t, kMaxFrame> prev_{};
  bool have_prev_ = false;
  bool in_sync_ = true;
  int last_dense_sync_ = 0;
  DecoderStats stats_;
  Message message_;
};

/// Variable-bit-scale decode of a 12-bit ultra-capsule major value (docs/protocols.md 1.8).
struct VarBitScale {
  std::uint32_t value_mm = 0;
  std::uint32_t level = 0;
};
[[nodiscard]] VarBitScale varbitscale_decode(std::uint32_t scaled);

}  // namespace coxswain::drivers::rplidar
