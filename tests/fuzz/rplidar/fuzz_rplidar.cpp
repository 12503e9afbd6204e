// SPDX-License-Identifier: Apache-2.0
// libFuzzer target: arbitrary bytes through the RPLIDAR Decoder (first byte picks the expected
// answer) and every produced node through the ScanAssembler. Checks the codec contract.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <span>

#include "coxswain/drivers/rplidar/answer_encoder.hpp"
#include "coxswain/drivers/rplidar/codec.hpp"
#include "coxswain/drivers/rplidar/scan_assembler.hpp"

using coxswain::drivers::rplidar::AnswerType;
using coxswain::drivers::rplidar::Decoder;
using coxswain::drivers::rplidar::MessageKind;
using coxswain::drivers::rplidar::ScanAssembler;
using coxswain::drivers::rplidar::ScanAssemblerParams;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  static const AnswerType kTypes[] = {AnswerType::kMeasurement,  AnswerType::kCapsule,
                                      AnswerType::kUltraCapsule, AnswerType::kDenseCapsule,
                                      AnswerType::kDevInfo,      AnswerType::kLidarConf};
  Decoder d;
  const std::uint8_t sel = data[0];
  if (sel % 7 == 6) {
    d.expect_any();
  } else {
    d.expect(kTypes[sel % 7]);
  }
  d.set_dense_sample_duration_us(sel & 0x80U ? 31U : 0U);
  ScanAssemblerParams p;
  p.mount.yaw_deg = static_cast<double>(sel) * 1.5;
  p.clockwise = (sel & 0x40U) == 0;
  p.sample_duration_us = 125.0;
  p.max_range_m = 40.0F;
  static auto assembler = std::make_unique<ScanAssembler>(p);
  *assembler = ScanAssembler(p);
  std::int64_t t = 0;
  if ((sel & 0x20U) != 0 && sel % 7 != 6) {
    // Start inside a stream so mutations explore the answer decoders, not only the hunt.
    const auto desc = coxswain::drivers::rplidar::encode_descriptor(kTypes[sel % 7]);
    std::span<const std::uint8_t> head(desc);
    while (!head.empty()) head = head.subspan(d.decode(head).consumed);
  }
  const std::uint64_t bytes_before = d.stats().codec.bytes_in;
  std::span<const std::uint8_t> rest(data + 1, size - 1);
  while (!rest.empty()) {
    const auto step = d.decode(rest);
    if (step.consumed == 0 || step.consumed > rest.size()) std::abort();
    rest = rest.subspan(step.consumed);
    if (!step.produced) continue;
    if (d.message().kind != MessageKind::kNodes) continue;
    if (d.message().nodes.count > d.message().nodes.nodes.size()) std::abort();
    for (const auto& n : d.message().nodes.span()) {
      if (assembler->add(n, t += 1000)) {
        const auto& s = assembler->scan();
        if (s.point_count > s.points.size()) std::abort();
        for (std::uint32_t k = 1; k < s.point_count; ++k) {
          if (s.points[k - 1].bearing_deg > s.points[k].bearing_deg) std::abort();
        }
      }
    }
  }
  if (d.stats().codec.bytes_in - bytes_before != size - 1) std::abort();
  return 0;
}
