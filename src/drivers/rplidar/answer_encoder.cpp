// SPDX-License-Identifier: Apache-2.0
#include "coxswain/drivers/rplidar/answer_encoder.hpp"

#include <algorithm>

#include "little_endian.hpp"

namespace coxswain::drivers::rplidar {

std::array<std::uint8_t, kDescriptorSize> encode_descriptor(AnswerType type, std::uint32_t size,
                                                            SendMode mode) {
  const std::uint32_t word = (size & 0x3FFFFFFFU) | (static_cast<std::uint32_t>(mode) << 30U);
  return {kSyncByte1,
          kSyncByte2,
          static_cast<std::uint8_t>(word & 0xFFU),
          static_cast<std::uint8_t>((word >> 8U) & 0xFFU),
          static_cast<std::uint8_t>((word >> 16U) & 0xFFU),
          static_cast<std::uint8_t>(word >> 24U),
          static_cast<std::uint8_t>(type)};
}

std::array<std::uint8_t, kDescriptorSize> encode_descriptor(AnswerType type) {
  switch (type) {
    case AnswerType::kDevInfo:
      return encode_descriptor(type, kDevInfoSize, SendMode::kSingle);
    case AnswerType::kHealth:
      return encode_descriptor(type, kHealthSize, SendMode::kSingle);
    case AnswerType::kSampleRate:
      return encode_descriptor(type, kSampleRateSize, SendMode::kSingle);
    case AnswerType::kAccBoardFlag:
      return encode_descriptor(type, kAccBoardFlagSize, SendMode::kSingle);
    case AnswerType::kMeasurement:
      return encode_descriptor(type, kNodeSize, SendMode::kContinuous);
    case AnswerType::kCapsule:
    case AnswerType::kDenseCapsule:
      return encode_descriptor(type, kCapsuleSize, SendMode::kContinuous);
    case AnswerType::kUltraCapsule:
      return encode_descriptor(type, kUltraCapsuleSize, SendMode::kContinuous);
    default:
      return encode_descriptor(type, 0, SendMode::kSingle);
  }
}

std::array<std::uint8_t, kNodeSize> encode_standard_node(bool start, std::uint8_t quality,
                                                         std::uint16_t angle_q6,
                                                         std::uint16_t distance_q2) {
  std::array<std::uint8_t, kNodeSize> n{};
  n[0] = static_cast<std::uint8_t>(((quality & 0x3FU) << 2U) | (start ? 0x01U : 0x02U));
  put_u16(n.data() + 1, static_cast<std::uint16_t>(((angle_q6 & 0x7FFFU) << 1U) | 1U));
  put_u16(n.data() + 3, distance_q2);
  return n;
}

void seal_capsule(std::span<std::uint8_t> capsule) {
  if (capsule.size() < 4) return;
  std::uint8_t x = 0;
  for (std::size_t i = 2; i < capsule.size(); ++i) x = static_cast<std::uint8_t>(x ^ capsule[i]);
  capsule[0] = static_cast<std::uint8_t>(0xA0U | (x & 0x0FU));
  capsule[1] = static_cast<std::uint8_t>(0x50U | (x >> 4U));
}

std::array<std::uint8_t, kDenseCapsuleSize> encode_dense_capsule(
    std::uint16_t start_angle_q6, bool restart, std::span<const std::uint16_t, 40> distances_mm) {
  std::array<std::uint8_t, kDenseCapsuleSize> c{};
  put_u16(c.data() + 2,
          static_cast<std::uint16_t>((start_angle_q6 & 0x7FFFU) | (restart ? 0x8000U : 0U)));
  for (std::size_t k = 0; k < 40; ++k) put_u16(c.data() + 4 + 2 * k, distances_mm[k]);
  seal_capsule(c);
  return c;
}

std::array<std::uint8_t, kDevInfoSize> encode_device_info(const DeviceInfo& info) {
  std::array<std::uint8_t, kDevInfoSize> a{};
  a[0] = info.model;
  a[1] = info.firmware_minor;
  a[2] = info.firmware_major;
  a[3] = info.hardware;
  std::copy(info.serial.begin(), info.serial.end(), a.begin() + 4);
  return a;
}

std::array<std::uint8_t, kHealthSize> encode_health(const Health& health) {
  std::array<std::uint8_t, kHealthSize> a{};
  a[0] = health.status;
  put_u16(a.data() + 1, health.error_code);
  return a;
}

std::array<std::uint8_t, kSampleRateSize> encode_sample_rate(const SampleRate& rate) {
  std::array<std::uint8_t, kSampleRateSize> a{};
  put_u16(a.data(), rate.standard_us);
  put_u16(a.data() + 2, rate.express_us);
  return a;
}

}  // namespace coxswain::drivers::rplidar
