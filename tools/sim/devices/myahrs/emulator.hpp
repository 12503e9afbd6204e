// SPDX-License-Identifier: Apache-2.0
#pragma once
// Byte-level myAHRS+ emulator core for the simulator (docs/architecture.md: the simulator injects
// bytes beneath the transport so the production codec runs). Protocol: docs/protocols.md
// section 2 (docs/protocols.md). Pure: no I/O, no clock (time is passed in), no
// allocation after construction, deterministic for a given seed.
//
// Behaviour emulated:
// - requests `@name[,args]*CC\r\n` (checksum verified; a bad checksum gets no answer, so the
//   host times out as with the real sensor) answered with `~name,OK,...` or `~name,ERROR`:
//   version, sn, id, ping, sensitivity, mode, asc_out, bin_out, divider, trig, save, factory;
// - data in the configured form: ASCII `$RPY|QUAT|RPYIMU|QUATIMU|IMU|RIIMU` or binary DLE frames
//   with nodes d (root), s, e, q, r, i; continuous mode every `divider` x 10 ms, trigger mode
//   one message per `@trig`;
// - faults: garbage bytes before data messages, corrupted checksums, total silence, and a rate
//   change at run time (set_divider: the sensor reconfigured behind the host's back).
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "coxswain/core/time.hpp"
#include "coxswain/drivers/myahrs/heading.hpp"
#include "coxswain/msg/imu_sample.hpp"
#include "sim/devices/device_emulator.hpp"

namespace coxswain::sim::devices::myahrs {

enum class AsciiFormat : std::uint8_t { kRpy, kQuat, kRpyImu, kQuatImu, kImu, kRiImu };

/// Binary content flags (`@bin_out` list).
struct BinaryFormat {
  bool euler = true;
  bool quaternion = false;
  bool raw_imu = false;
  bool imu = true;
};

struct EmulatorFaults {
  double garbage_probability = 0.0;           // per data message: 1..16 random bytes sent before it
  double corrupt_checksum_probability = 0.0;  // per data message: checksum XOR 0x5A
  bool silent = false;                        // sends nothing at all (dead sensor, cut cable)
  std::uint64_t seed = 1;                     // fault PRNG seed (deterministic runs)

  [[nodiscard]] std::optional<std::string> validate() const;
};

/// Power-on state (the real sensor's volatile settings: see docs/protocols.md 2.1) and faults.
struct EmulatorConfig {
  bool binary = false;     // mode letter A/B
  bool continuous = true;  // mode letter C/T
  AsciiFormat ascii_format = AsciiFormat::kRpyImu;
  BinaryFormat binary_format{};
  int divider = 1;  // rate = 100 / divider Hz
  EmulatorFaults faults{};

  [[nodiscard]] std::optional<std::string> validate() const;
};

/// Counters of what the emulator did (for scenario assertions).
struct EmulatorStats {
  std::uint64_t requests_ok = 0;
  std::uint64_t requests_bad_checksum = 0;
  std::uint64_t error_responses = 0;
  std::uint64_t data_messages = 0;
  std::uint64_t garbage_bursts = 0;
  std::uint64_t corrupted_messages = 0;
  std::uint64_t skipped_ticks = 0;  // data periods dropped after a large time jump
  std::uint64_t dropped_bytes = 0;  // output buffer full (caller did not poll)
};

/// The myAHRS+ as seen from its serial port. Thread-safety: none (the simulator drives it).
class Emulator final : public DeviceEmulator {
 public:
  static constexpr std::size_t kOutputCapacity = 16384;
  static constexpr std::size_t kLineCapacity = 256;
  static constexpr std::int64_t kBasePeriodNs = 10'000'000;  // 100 Hz
  /// At most this many data periods are caught up in one poll; older ones are skipped.
  static constexpr int kMaxCatchUpTicks = 10;

  explicit Emulator(const EmulatorConfig& config = {});

  /// The sensor's current outputs: roll, pitch, yaw_magnetic_deg (sensor frame, magnetic),
  /// accel_g, gyro_dps, mag_ut, temperature_c. Other fields are ignored.
  void set_truth(const msg::ImuSample& truth) { truth_ = truth; }

  /// Bytes written by the host (requests), split anywhere. Responses are queued for poll().
  void receive(std::span<const std::uint8_t> host_bytes);
  /// DeviceEmulator: the sensor's answers do not depend on when a request arrives.
  void receive(std::span<const std::uint8_t> host_bytes, core::TimeNs now_ns) override;

  /// Everything the sensor sends up to `now_ns`: queued responses, then data due in continuous
  /// mode. The view is valid until the next poll().
  [[nodiscard]] std::span<const std::uint8_t> poll(core::TimeNs now_ns) override;

  /// Run-time fault changes (silence on/off, garbage, corruption); the PRNG keeps its state.
  void set_faults(const EmulatorFaults& faults) { config_.faults = faults; }
  /// Run-time rate change: output every `divider` x 10 ms from now on (clamped to [1, 1000]).
  void set_divider(int divider);

  [[nodiscard]] const EmulatorStats& stats() const { return stats_; }
  [[nodiscard]] int divider() const { return divider_; }
  [[nodiscard]] bool binary() const { return binary_; }
  [[nodiscard]] bool continuous() const { return continuous_; }

  /// Sensor yaw the emulator should report for a true bow heading: the inverse of
  /// drivers::myahrs::true_heading_deg(), in (-180, 180].
  [[nodiscard]] static double sensor_yaw_for_heading(double true_heading_deg,
                                                     const drivers::myahrs::HeadingConfig& cfg);

 private:
  void handle_line();
  void respond(const char* text);  // text without '*CC\r\n'
  void respond_error(std::string_view name);
  void apply_config(const EmulatorConfig& c);
  void emit_data();
  void emit_ascii();
  void emit_binary();
  void put(std::span<const std::uint8_t> bytes);
  void put_line(const char* body, std::size_t n, bool may_corrupt);  // appends *CC\r\n
  [[nodiscard]] std::uint64_t next_random();
  [[nodiscard]] double uniform();

  EmulatorConfig config_;
  bool binary_;
  bool continuous_;
  AsciiFormat ascii_format_;
  BinaryFormat binary_format_;
  int divider_;
  int id_ = 0;
  msg::ImuSample truth_{};
  std::uint8_t sequence_ = 0;
  std::uint64_t rng_state_;
  core::TimeNs next_data_ns_ = core::kNeverNs;
  bool corrupt_next_ = false;

  std::array<char, kLineCapacity> line_{};
  std::size_t line_len_ = 0;
  bool in_line_ = false;

  std::array<std::uint8_t, kOutputCapacity> out_{};
  std::size_t out_len_ = 0;
  std::size_t returned_ = 0;
  EmulatorStats stats_;
};

}  // namespace coxswain::sim::devices::myahrs
