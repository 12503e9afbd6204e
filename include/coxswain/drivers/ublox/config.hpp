// SPDX-License-Identifier: Apache-2.0
#pragma once
// Pure encoders for u-blox receiver configuration: UBX frames with checksum, F9 CFG-VALSET (RAM
// layer) and M8 legacy CFG-MSG / CFG-RATE / CFG-NAV5, and the ordered configuration plan an
// adapter sends (each frame waits for its ACK-ACK, with retries). Protocol facts:
// docs/protocols.md sections 3.2, 3.5, 3.6, 3.7.
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "coxswain/drivers/ublox/codec.hpp"

namespace coxswain::drivers::ublox {

/// Largest configuration frame the encoders build (a VALSET with ~40 one-byte keys fits).
inline constexpr std::size_t kMaxConfigFrameBytes = 256;

/// One complete UBX frame (sync .. checksum) in a fixed buffer. Value type, no allocation.
struct UbxFrame {
  std::array<std::uint8_t, kMaxConfigFrameBytes> data{};
  std::size_t size = 0;  // 0 = not built (payload too large)
  [[nodiscard]] std::span<const std::uint8_t> bytes() const { return {data.data(), size}; }
  [[nodiscard]] UbxId id() const { return size >= 4 ? UbxId{data[2], data[3]} : UbxId{}; }
};

/// Builds B5 62 class id len payload CK_A CK_B. Returns a frame with size 0 if the payload does
/// not fit kMaxConfigFrameBytes.
[[nodiscard]] UbxFrame make_ubx_frame(UbxId id, std::span<const std::uint8_t> payload);

inline constexpr UbxId kCfgMsg{0x06, 0x01};
inline constexpr UbxId kCfgRate{0x06, 0x08};
inline constexpr UbxId kCfgNav5{0x06, 0x24};
inline constexpr UbxId kCfgValset{0x06, 0x8A};
inline constexpr UbxId kNavPvt{0x01, 0x07};
inline constexpr UbxId kNavHpPosLlh{0x01, 0x14};

/// F9 configuration keys used here (docs/protocols.md 3.6).
namespace key {
inline constexpr std::uint32_t kRateMeas = 0x30210001;        // U2 ms
inline constexpr std::uint32_t kRateNav = 0x30210002;         // U2 cycles
inline constexpr std::uint32_t kNavspgDynModel = 0x20110021;  // E1, 5 = sea
inline constexpr std::uint32_t kUart1OutProtUbx = 0x10740001;
inline constexpr std::uint32_t kUart1OutProtNmea = 0x10740002;
inline constexpr std::uint32_t kUsbOutProtUbx = 0x10780001;
inline constexpr std::uint32_t kUsbOutProtNmea = 0x10780002;
inline constexpr std::uint32_t kMsgoutNavPvtUart1 = 0x20910007;
inline constexpr std::uint32_t kMsgoutNavPvtUsb = 0x20910009;
inline constexpr std::uint32_t kMsgoutNmeaGgaUart1 = 0x209100BB;
inline constexpr std::uint32_t kMsgoutNmeaGgaUsb = 0x209100BD;
inline constexpr std::uint32_t kMsgoutNmeaRmcUart1 = 0x209100AC;
inline constexpr std::uint32_t kMsgoutNmeaRmcUsb = 0x209100AE;
}  // namespace key

/// Value size in bytes from a key id (bits 28-30: 1 bit -> 1 byte, 1, 2, 4, 8); 0 if invalid.
[[nodiscard]] std::size_t valset_value_size(std::uint32_t key_id);

/// Accumulates {key, value} pairs for one CFG-VALSET (version 0, no transaction) frame.
/// Value type, fixed capacity; add() fails if the value does not fit the key's size or the
/// frame would overflow.
class ValsetBuilder {
 public:
  /// layers: bit0 RAM, bit1 BBR, bit2 Flash.
  explicit ValsetBuilder(std::uint8_t layers = 0x01);
  [[nodiscard]] bool add(std::uint32_t key_id, std::uint64_t value);
  [[nodiscard]] UbxFrame build() const;

 private:
  std::array<std::uint8_t, kMaxConfigFrameBytes - 8> payload_{};
  std::size_t size_ = 4;
};

/// Receiver generation: M8 (protocol < 27, legacy CFG messages) or F9 (CFG-VALSET).
enum class Generation : std::uint8_t { kM8, kF9 };
/// Port the host talks on (and where output is enabled).
enum class Port : std::uint8_t { kUsb, kUart1 };

/// Dynamic platform model values (CFG-NAV5 dynModel / CFG-NAVSPG-DYNMODEL).
inline constexpr std::uint8_t kDynModelSea = 5;

// ---- Single-purpose frames ----

/// F9: measurement period for `rate_hz` (CFG-RATE-MEAS, RAM), e.g. 10 Hz -> 100 ms.
[[nodiscard]] UbxFrame f9_set_meas_period(std::uint16_t period_ms);
/// F9: NAV-PVT output every `every_n` navigation epochs (0 = off) on `port` (RAM).
[[nodiscard]] UbxFrame f9_set_nav_pvt_output(Port port, std::uint8_t every_n);
/// F9: dynamic platform model (RAM).
[[nodiscard]] UbxFrame f9_set_dyn_model(std::uint8_t model);
/// F9: output protocols on `port`: UBX on, NMEA as given; with NMEA on also GGA and RMC every
/// epoch (RAM).
[[nodiscard]] UbxFrame f9_set_output_protocols(Port port, bool nmea_enabled);
/// M8: CFG-MSG rate of `id` on the port the frame arrives on (3-byte form).
[[nodiscard]] UbxFrame m8_set_msg_rate(UbxId id, std::uint8_t every_n);
/// M8: CFG-RATE measRate ms, navRate 1, timeRef (0 UTC, 1 GPS).
[[nodiscard]] UbxFrame m8_set_rate(std::uint16_t meas_period_ms, std::uint8_t time_ref = 1);
/// M8: CFG-NAV5 applying only dynModel (mask bit0).
[[nodiscard]] UbxFrame m8_set_dyn_model(std::uint8_t model);

// ---- Configuration plan ----

/// What the adapter wants from the receiver. Units in names; defaults suit a boat.
struct ConfigParams {
  double rate_hz = 5.0;       // navigation solutions per second (M8 <= 10, F9 <= 20)
  Port port = Port::kUsb;     // the port coxswain is connected to
  bool nmea_enabled = false;  // keep GGA/RMC on the port (for other listeners / debugging)

  /// nullopt if valid for `gen`, otherwise a message naming the bad field.
  [[nodiscard]] std::optional<std::string> validate(Generation gen) const;
  /// Measurement period in ms for rate_hz (rounded), as sent to the receiver.
  [[nodiscard]] std::uint16_t meas_period_ms() const;
};

/// One step: send `frame`, then wait for ACK-ACK whose payload equals `ack_for`.
struct ConfigStep {
  UbxFrame frame;
  UbxId ack_for;
  std::string_view what;  // short description for logs (static string)
};

/// Ordered configuration frames for one receiver. Value type, fixed capacity.
struct ConfigPlan {
  static constexpr std::size_t kMaxSteps = 12;
  std::array<ConfigStep, kMaxSteps> steps{};
  std::size_t count = 0;
  [[nodiscard]] std::span<const ConfigStep> view() const { return {steps.data(), count}; }
};

/// The plan for `gen` and `params`. Precondition: params.validate(gen) is nullopt (otherwise
/// an empty plan is returned). RAM layer only: the receiver's saved configuration is untouched.
/// F9: rate, dynamic model sea, output protocols (+GGA/RMC if NMEA), NAV-PVT every epoch.
/// M8: CFG-RATE, CFG-NAV5 sea, CFG-MSG NAV-PVT 1, then NMEA GGA/RMC on (or the six standard
/// NMEA sentences off) via CFG-MSG on the current port.
[[nodiscard]] ConfigPlan make_config_plan(Generation gen, const ConfigParams& params);

}  // namespace coxswain::drivers::ublox
