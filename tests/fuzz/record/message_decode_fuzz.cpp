// SPDX-License-Identifier: Apache-2.0
// libFuzzer target for the recording's message decoders, protobuf and the legacy packed layouts:
// the first byte picks the message type, the rest is its bytes. Contract: no crash, no read past
// the input, and a protobuf message that decodes re-encodes within the bounds the recorder's
// slots assume.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <span>
#include <vector>

#include "coxswain/record/proto_codec.hpp"

namespace {

using namespace coxswain;

template <class T>
void sample(std::span<const std::uint8_t> in, std::size_t max_bytes) {
  static const auto m = std::make_unique<T>();
  static std::vector<std::uint8_t> out(max_bytes);
  std::uint64_t sequence = 0;
  if (record::proto::decode_sample(in, sequence, *m) &&
      record::proto::encode_sample(out, sequence, *m) == 0) {
    std::abort();  // a message we read must fit what the recorder writes
  }
  (void)record::decode_sample(in, sequence, *m);  // the legacy layout
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::span<const std::uint8_t> in(data + 1, size - 1);
  switch (data[0] % 10) {
    case 0:
      sample<msg::GnssFix>(in, 1024);
      break;
    case 1:
      sample<msg::ImuSample>(in, 1024);
      break;
    case 2:
      sample<msg::LidarScan>(in, record::proto::kMaxLidarBytes);
      break;
    case 3:
      sample<msg::CameraDetections>(in, 1024);
      break;
    case 4:
      sample<msg::ArduinoStatus>(in, 1024);
      break;
    case 5:
      sample<msg::OperatorInput>(in, 1024);
      break;
    case 6:
      sample<msg::DeviceHealth>(in, 1024);
      break;
    case 7: {
      static const auto tick = std::make_unique<record::TickRecordData>();
      (void)record::decode_tick(record::Encoding::kProtobuf, in, *tick);
      (void)record::decode_tick(record::Encoding::kLegacyBinary, in, *tick);
      break;
    }
    case 8: {
      record::RawRecord raw;
      (void)record::decode_raw(record::Encoding::kProtobuf, in, raw);
      (void)record::decode_raw(record::Encoding::kLegacyBinary, in, raw);
      break;
    }
    default: {
      record::ParameterSetRecord set;
      (void)record::decode_parameters(record::Encoding::kProtobuf, in, set);
      (void)record::decode_parameters(record::Encoding::kLegacyBinary, in, set);
      break;
    }
  }
  return 0;
}
