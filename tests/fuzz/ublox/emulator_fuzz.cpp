// SPDX-License-Identifier: Apache-2.0
// Fuzzes the parsers added with the u-blox emulator and session: the emulator's host-input
// handling (CFG-VALSET/MSG/RATE/PRT/NAV5 payloads, RTCM counting), capture splitting and
// pacing, and UbloxSession's byte handling (stamping, preference rule, ACK matching).
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "coxswain/drivers/ublox/session.hpp"
#include "sim/devices/ublox/emulator.hpp"

namespace {

struct NullLink final : coxswain::drivers::DeviceLink {
  bool write(std::span<const std::uint8_t> /*bytes*/) override { return true; }
  void set_dtr(bool /*asserted*/) override {}
  void flush_input() override {}
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace coxswain;
  const std::span<const std::uint8_t> in(data, size);
  const std::size_t split = size == 0 ? 0 : data[0] % size;
  for (const auto model : {sim::devices::ublox::Model::kF9, sim::devices::ublox::Model::kM8}) {
    sim::devices::ublox::EmulatorConfig cfg;
    cfg.model = model;
    sim::devices::ublox::Emulator emu(cfg);
    emu.receive(in.first(split), 0);
    emu.receive(in.subspan(split), 0);
    (void)emu.poll(5 * core::kNsPerSec);
  }
  const sim::devices::ublox::Capture capture(std::vector<std::uint8_t>(in.begin(), in.end()));
  sim::devices::ublox::Emulator replay;
  replay.play_capture(&capture);
  (void)replay.poll(0);
  (void)replay.poll(capture.duration_ns());

  core::LatestSlot<msg::GnssFix> slot;
  config::GnssDeviceConfig gcfg;
  drivers::ublox::UbloxSession session(gcfg, slot);
  NullLink link;
  session.on_open(link, 0);
  session.on_bytes(in.first(split), 1, link);
  session.on_bytes(in.subspan(split), 2, link);
  (void)session.on_poll(link, 3);
  msg::DeviceHealth h;
  session.fill_health(h, 4);
  return 0;
}
