// SPDX-License-Identifier: Apache-2.0
#pragma once
// The lidar's side of the protocol (docs/protocols.md 1.4-1.9): builds response descriptors, single
// answers, standard nodes and capsules. For device emulators (the simulator) and for tests, which
// have no raw standard-mode capture to replay. Pure, fixed-size outputs.
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "coxswain/drivers/rplidar/protocol.hpp"

namespace coxswain::drivers::rplidar {

/// `A5 5A len|mode<<30 type`.
[[nodiscard]] std::array<std::uint8_t, kDescriptorSize> encode_descriptor(AnswerType type,
                                                                          std::uint32_t size,
                                                                          SendMode mode);
/// Descriptor for a known answer type with its standard size and send mode.
[[nodiscard]] std::array<std::uint8_t, kDescriptorSize> encode_descriptor(AnswerType type);

/// One standard node (answer 0x81). angle_q6 in 1/64 degree (< 23040), quality 0..63.
[[nodiscard]] std::array<std::uint8_t, kNodeSize> encode_standard_node(bool start,
                                                                       std::uint8_t quality,
                                                                       std::uint16_t angle_q6,
                                                                       std::uint16_t distance_q2);

/// One dense capsule (answer 0x85) with a valid checksum: 40 distances in mm.
[[nodiscard]] std::array<std::uint8_t, kDenseCapsuleSize> encode_dense_capsule(
    std::uint16_t start_angle_q6, bool restart, std::span<const std::uint16_t, 40> distances_mm);

/// Writes the capsule checksum nibbles of an express/dense/ultra capsule in place.
void seal_capsule(std::span<std::uint8_t> capsule);

[[nodiscard]] std::array<std::uint8_t, kDevInfoSize> encode_device_info(const DeviceInfo& info);
[[nodiscard]] std::array<std::uint8_t, kHealthSize> encode_health(const Health& health);
[[nodiscard]] std::array<std::uint8_t, kSampleRateSize> encode_sample_rate(const SampleRate& rate);

}  // namespace coxswain::drivers::rplidar
