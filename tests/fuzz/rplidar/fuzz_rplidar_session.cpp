// SPDX-License-Identifier: Apache-2.0
// libFuzzer target: the RplidarSession (start-up state machine, stamping, assembly, health) fed
// hostile device bytes at fuzzer-chosen times. Two modes, picked by the first byte:
//  - raw (3 inputs in 4): the input itself is the device's byte stream, in fuzzer-sized chunks;
//  - emulated (first byte >= 0xC0, slower): the RPLIDAR emulator answers the session (so the fuzzer
//  reaches the scanning
//    states), and the input flips bits and inserts bytes in the emulator's output.
// Checks: no crash/UB, and every published revolution is well formed.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "coxswain/drivers/rplidar/session.hpp"
#include "sim/devices/rplidar/emulator.hpp"

namespace {

using coxswain::core::TimeNs;
namespace rp = coxswain::drivers::rplidar;
namespace emu = coxswain::sim::devices::rplidar;

class Link final : public coxswain::drivers::DeviceLink {
 public:
  emu::Emulator* emulator = nullptr;
  TimeNs now_ns = 0;
  bool write(std::span<const std::uint8_t> bytes) override {
    if (emulator != nullptr) emulator->receive(bytes, now_ns);
    return true;
  }
  void set_dtr(bool asserted) override {
    if (emulator != nullptr) emulator->set_dtr(asserted);
  }
  void flush_input() override {}
};

void check_scan(const coxswain::msg::LidarScan& s) {
  if (s.point_count > coxswain::msg::LidarScan::kMaxPoints) std::abort();
  for (std::uint32_t i = 0; i < s.point_count; ++i) {
    const auto& p = s.points[i];
    if (!(p.bearing_deg > -180.0F && p.bearing_deg <= 180.0F)) std::abort();
    if (!(p.range_m >= 0.0F)) std::abort();
    if (i > 0 && s.points[i - 1].bearing_deg > p.bearing_deg) std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  const std::uint8_t sel = data[0];
  std::span<const std::uint8_t> in(data + 1, size - 1);
  coxswain::config::LidarDeviceConfig cfg;
  cfg.scan_mode = static_cast<coxswain::config::LidarScanMode>(sel % 3);
  cfg.timeout_ms = 200 + 100U * ((sel >> 2) % 8);
  static coxswain::core::LatestSlot<coxswain::msg::LidarScan> slot;
  // Made afresh for every input, in storage kept between inputs: a session holds two full
  // scans, and a new heap block of that size costs the sanitizer a mapping and its page faults.
  static std::optional<rp::RplidarSession> session_storage;
  session_storage.reset();
  rp::RplidarSession& session =
      session_storage.emplace(cfg, coxswain::core::MountTransform{180.0, 0.0, 0.0}, slot);
  Link link;
  TimeNs now = 1'000'000'000;
  link.now_ns = now;
  const std::uint64_t published_before = slot.sequence();

  if ((sel & 0xC0U) != 0xC0U) {
    session.on_open(link, now);
    // Chunks: [dt_ms][len] then len bytes.
    while (in.size() >= 2) {
      now += static_cast<TimeNs>(in[0]) * 1'000'000;
      const std::size_t len = std::min<std::size_t>(in[1], in.size() - 2);
      link.now_ns = now;
      session.on_bytes(in.subspan(2, len), now, link);
      if (session.on_poll(link, now) == coxswain::drivers::SessionVerdict::kReopen) {
        session.on_close(now);
        session.on_open(link, now);
      }
      in = in.subspan(2 + len);
    }
  } else {
    emu::EmulatorConfig ec;
    // S2 (32 kSa/s) is left out: it makes each input ten times slower for no new code path.
    static constexpr emu::Model kModels[] = {emu::Model::kA1, emu::Model::kA2, emu::Model::kA3,
                                             emu::Model::kS1, emu::Model::kC1};
    ec.model = kModels[(sel >> 2) % 5];
    ec.spin_up_ms = 0;
    static std::optional<emu::Emulator> emulator_storage;
    emulator_storage.reset();
    emu::Emulator& e = emulator_storage.emplace(ec);
    std::vector<float> ranges(360);
    for (std::size_t i = 0; i < ranges.size(); ++i)
      ranges[i] = 0.5F + 0.01F * static_cast<float>(i);
    e.set_ranges(ranges);
    link.emulator = &e;
    session.on_open(link, now);
    std::vector<std::uint8_t> buf;
    std::size_t k = 0;
    for (int step = 0; step < 30; ++step) {  // 300 ms: start-up and two revolutions
      now += 10'000'000;
      link.now_ns = now;
      const auto out = e.poll(now);
      buf.assign(out.begin(), out.end());
      // Input pairs [op][arg]: flip a bit at a position, or insert a byte.
      if (k + 1 < in.size() && !buf.empty()) {
        const std::uint8_t op = in[k];
        const std::uint8_t arg = in[k + 1];
        k += 2;
        const std::size_t pos = (static_cast<std::size_t>(op) * 131 + arg) % buf.size();
        if ((op & 1U) != 0) {
          buf[pos] = static_cast<std::uint8_t>(buf[pos] ^ (1U << (arg % 8)));
        } else {
          buf.insert(buf.begin() + static_cast<std::ptrdiff_t>(pos), arg);
        }
      }
      session.on_bytes(buf, now, link);
      if (session.on_poll(link, now) == coxswain::drivers::SessionVerdict::kReopen) {
        session.on_close(now);
        session.on_open(link, now);
      }
    }
  }
  if (slot.sequence() != published_before) check_scan(slot.read().value);
  coxswain::msg::DeviceHealth h;
  session.fill_health(h, now);
  if (h.detail[h.detail.size() - 1] != '\0') std::abort();
  return 0;
}
