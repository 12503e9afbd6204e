// SPDX-License-Identifier: Apache-2.0
// The myAHRS+ emulator core through the DeviceEmulator interface the pty host uses, and its
// run-time faults: rate change (divider), silence switched on and off.
#include <gtest/gtest.h>

#include <memory>

#include "coxswain/drivers/myahrs/codec.hpp"
#include "coxswain/drivers/myahrs/commands.hpp"
#include "sim/devices/myahrs/emulator.hpp"

namespace coxswain::sim::devices::myahrs {
namespace {

constexpr core::TimeNs kMs = core::kNsPerMs;

std::size_t samples_in(drivers::myahrs::Decoder& d, std::span<const std::uint8_t> bytes) {
  std::size_t n = 0;
  while (!bytes.empty()) {
    const auto step = d.decode(bytes);
    bytes = bytes.subspan(step.consumed);
    if (step.produced && d.last_output() == drivers::myahrs::Output::kSample) ++n;
  }
  return n;
}

TEST(MyahrsEmulatorRuntime, DrivenThroughDeviceEmulatorWithRateChangeAndSilence) {
  Emulator core;
  DeviceEmulator& dev = core;  // what sim::pty::EmulatorHost holds
  drivers::myahrs::Decoder d;
  // A request through the interface is answered.
  dev.receive(drivers::myahrs::divider_command(4)->data(), 0);
  (void)samples_in(d, dev.poll(0));
  EXPECT_EQ(core.divider(), 4);
  EXPECT_EQ(core.stats().requests_ok, 1U);
  std::size_t n = 0;
  for (core::TimeNs t = 10 * kMs; t <= 1'000 * kMs; t += 10 * kMs) n += samples_in(d, dev.poll(t));
  EXPECT_NEAR(static_cast<double>(n), 25.0, 1.0);  // 100 / 4 Hz
  // Rate change behind the host's back.
  core.set_divider(1);
  n = 0;
  for (core::TimeNs t = 1'010 * kMs; t <= 2'000 * kMs; t += 10 * kMs)
    n += samples_in(d, dev.poll(t));
  // The sample already scheduled 40 ms ahead comes first, then every 10 ms: 97 in this second.
  EXPECT_NEAR(static_cast<double>(n), 97.0, 1.0);
  core.set_divider(0);  // clamped
  EXPECT_EQ(core.divider(), 1);
  // Silence on: nothing, not even answers; off again: data resumes.
  EmulatorFaults quiet;
  quiet.silent = true;
  core.set_faults(quiet);
  dev.receive(drivers::myahrs::version_command().data(), 2'000 * kMs);
  for (core::TimeNs t = 2'010 * kMs; t <= 2'500 * kMs; t += 10 * kMs) {
    EXPECT_TRUE(dev.poll(t).empty());
  }
  core.set_faults({});
  n = 0;
  for (core::TimeNs t = 2'510 * kMs; t <= 3'000 * kMs; t += 10 * kMs)
    n += samples_in(d, dev.poll(t));
  EXPECT_NEAR(static_cast<double>(n), 50.0, 1.0);
  EXPECT_EQ(d.stats().codec.checksum_errors, 0U);
}

}  // namespace
}  // namespace coxswain::sim::devices::myahrs
