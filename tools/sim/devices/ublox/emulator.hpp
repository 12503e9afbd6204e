// SPDX-License-Identifier: Apache-2.0
#pragma once
// Byte-level u-blox receiver emulator core (M8 or ZED-F9P) for the simulator. Protocol:
// docs/protocols.md section 3. Pure: no I/O, no clock (time is passed in), no
// allocation after construction (a capture is loaded by its owner beforehand), deterministic for
// a seed.
//
// Behaviour emulated:
// - host input split anywhere; UBX frames with a bad checksum are ignored (no answer, as the real
//   receiver does), RTCM 3 frames are counted (CRC-checked);
// - CFG-VALSET (F9 only: an M8, protocol < 27, does not know it and NAKs it), CFG-MSG,
//   CFG-RATE, CFG-PRT, CFG-NAV5 answered with ACK-ACK, or ACK-NAK when malformed (wrong length,
//   unknown VALSET key, impossible rate). The F9 still accepts these legacy messages
//   (docs/protocols.md 3.7 "still accepted on F9 for some items"; a CFG-PRT baud change is not
//   honoured there, which this core has no baud to model anyway). Other CFG messages: NAK.
//   Polls (CFG-MSG 2 bytes, CFG-RATE/CFG-PRT empty or 1 byte) are answered with the current
//   setting then ACK-ACK;
// - navigation epochs every measurement period: NAV-PVT when enabled, then NMEA RMC and GGA when
//   NMEA output and those sentences are enabled (u-blox order: RMC before GGA), built from the
//   truth set by the owner (set_truth) or replayed from a recorded capture (play_capture);
// - power-on state as the real receivers: 1 Hz, NMEA on (GGA, RMC), NAV-PVT off;
// - faults: garbage before an epoch, corrupted checksums, total silence, and a rate change at
//   run time (set_rate_hz: another tool reconfigured the receiver).
#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "coxswain/core/time.hpp"
#include "coxswain/drivers/ublox/codec.hpp"
#include "coxswain/msg/gnss_fix.hpp"
#include "sim/devices/device_emulator.hpp"

namespace coxswain::sim::devices::ublox {

enum class Model : std::uint8_t { kM8, kF9 };
/// The port the host is connected to (whose output settings the host changes).
enum class HostPort : std::uint8_t { kUsb, kUart1 };

struct EmulatorFaults {
  double garbage_probability = 0.0;           // per epoch: 1..16 random bytes before it
  double corrupt_checksum_probability = 0.0;  // per output message: checksum damaged
  bool silent = false;                        // sends nothing at all (dead receiver, cut cable)
  std::uint64_t seed = 1;

  [[nodiscard]] std::optional<std::string> validate() const;
};

/// Power-on settings and faults.
struct EmulatorConfig {
  Model model = Model::kF9;
  HostPort port = HostPort::kUsb;
  double rate_hz = 1.0;  // power-on navigation rate
  bool nav_pvt = false;  // power-on: NMEA only
  bool nmea = true;      // NMEA output protocol with GGA and RMC
  EmulatorFaults faults{};

  [[nodiscard]] std::optional<std::string> validate() const;
};

struct EmulatorStats {
  std::uint64_t acks = 0;
  std::uint64_t naks = 0;
  std::uint64_t host_frames = 0;      // checksum-valid UBX frames received
  std::uint64_t host_bad_frames = 0;  // UBX/RTCM frames with a bad checksum (ignored)
  std::uint64_t rtcm_frames = 0;      // CRC-valid RTCM 3 frames received
  std::uint64_t rtcm_bytes = 0;
  std::uint64_t epochs = 0;
  std::uint64_t nav_pvt_sent = 0;
  std::uint64_t nmea_sent = 0;
  std::uint64_t capture_frames_sent = 0;
  std::uint64_t garbage_bursts = 0;
  std::uint64_t corrupted_messages = 0;
  std::uint64_t skipped_epochs = 0;  // epochs dropped after a large time jump
  std::uint64_t dropped_bytes = 0;   // output buffer full (owner did not poll)
};

/// A raw receiver capture (UBX/NMEA/RTCM mixed) split into frames, each with a release time
/// relative to the first: NAV-class UBX frames by their iTOW (payload offset 0; 4 for
/// HPPOSLLH), NMEA GGA/RMC/GLL/ZDA by their UTC time of day when no UBX time was seen; other
/// frames inherit the time of the frame before them. Built once by the owner (allocates).
class Capture {
 public:
  struct Frame {
    std::size_t offset = 0;
    std::size_t size = 0;
    core::TimeNs at_ns = 0;  // since the first frame
  };
  /// From raw bytes (a gpsd .log with its leading '#' lines removed, a .ubx, an .nmea ...).
  explicit Capture(std::vector<std::uint8_t> bytes);
  /// From a plain (not compressed) file; nullopt when it cannot be read.
  [[nodiscard]] static std::optional<Capture> load(const std::filesystem::path& path);

  [[nodiscard]] std::span<const Frame> frames() const { return frames_; }
  [[nodiscard]] std::span<const std::uint8_t> bytes(const Frame& f) const {
    return std::span<const std::uint8_t>(bytes_).subspan(f.offset, f.size);
  }
  [[nodiscard]] core::TimeNs duration_ns() const {
    return frames_.empty() ? 0 : frames_.back().at_ns;
  }

 private:
  std::vector<std::uint8_t> bytes_;
  std::vector<Frame> frames_;
};

/// The receiver as seen from its serial port. Thread-safety: none (one owner drives it).
class Emulator final : public DeviceEmulator {
 public:
  static constexpr std::size_t kOutputCapacity = 65536;
  static constexpr int kMaxCatchUpEpochs = 5;

  explicit Emulator(const EmulatorConfig& config = {});

  /// The receiver's current solution; every field the decoder reads is encoded (UTC from
  /// utc_ns, 0 = no valid time; iTOW from itow_ms, or from utc_ns when itow_ms is 0).
  void set_truth(const msg::GnssFix& truth) { truth_ = truth; }
  /// Replays `capture` from the next poll on, paced by its times, instead of the truth. The
  /// capture must outlive its replay. nullptr returns to the truth.
  void play_capture(const Capture* capture);
  [[nodiscard]] bool capture_finished() const;

  void set_faults(const EmulatorFaults& faults) { config_.faults = faults; }
  /// Run-time rate change (e.g. another tool reconfigured the receiver).
  void set_rate_hz(double rate_hz);

  void receive(std::span<const std::uint8_t> host_bytes, core::TimeNs now_ns) override;
  [[nodiscard]] std::span<const std::uint8_t> poll(core::TimeNs now_ns) override;

  [[nodiscard]] const EmulatorStats& stats() const { return stats_; }
  [[nodiscard]] std::uint16_t meas_period_ms() const { return meas_period_ms_; }
  [[nodiscard]] std::uint8_t nav_pvt_rate() const { return nav_pvt_rate_; }
  [[nodiscard]] bool nmea_output() const { return nmea_out_; }
  [[nodiscard]] std::uint8_t dyn_model() const { return dyn_model_; }
  [[nodiscard]] Model model() const { return config_.model; }

 private:
  void handle_ubx(std::span<const std::uint8_t> frame);
  [[nodiscard]] bool handle_valset(std::span<const std::uint8_t> payload);
  [[nodiscard]] bool handle_cfg_msg(std::span<const std::uint8_t> payload);
  [[nodiscard]] bool handle_cfg_rate(std::span<const std::uint8_t> payload);
  [[nodiscard]] bool handle_cfg_prt(std::span<const std::uint8_t> payload);
  void send_ack(std::uint8_t cls, std::uint8_t id, bool ack);
  void send_ubx(std::uint8_t cls, std::uint8_t id, std::span<const std::uint8_t> payload,
                bool may_corrupt);
  void send_nmea(const char* body, std::size_t n);
  void emit_epoch();
  void emit_nav_pvt();
  void emit_rmc();
  void emit_gga();
  void put(std::span<const std::uint8_t> bytes);
  [[nodiscard]] std::uint64_t next_random();
  [[nodiscard]] double uniform();
  [[nodiscard]] std::uint32_t itow_ms() const;
  void set_msg_rate(std::uint8_t cls, std::uint8_t id, std::uint8_t rate);
  [[nodiscard]] std::uint8_t msg_rate(std::uint8_t cls, std::uint8_t id) const;

  EmulatorConfig config_;
  std::uint16_t meas_period_ms_;
  std::uint8_t nav_pvt_rate_;
  std::uint8_t gga_rate_ = 1;
  std::uint8_t rmc_rate_ = 1;
  bool ubx_out_ = true;
  bool nmea_out_;
  std::uint8_t dyn_model_ = 0;  // portable
  msg::GnssFix truth_{};
  std::uint64_t epoch_counter_ = 0;
  std::uint64_t rng_state_;
  core::TimeNs next_epoch_ns_ = core::kNeverNs;

  const Capture* capture_ = nullptr;
  std::size_t capture_next_ = 0;
  core::TimeNs capture_start_ns_ = core::kNeverNs;

  drivers::ublox::FrameScanner host_scanner_{
      drivers::ublox::ProtocolMask{.ubx = true, .nmea = false, .rtcm3 = true}};

  std::array<std::uint8_t, kOutputCapacity> out_{};
  std::size_t out_len_ = 0;
  std::size_t returned_ = 0;
  EmulatorStats stats_;
};

}  // namespace coxswain::sim::devices::ublox
