// SPDX-License-Identifier: Apache-2.0
#pragma once
// Byte-level RPLIDAR emulator core for the simulator (docs/architecture.md). Protocol:
// docs/protocols.md section 1. Pure: no I/O, no clock (time is passed in), deterministic for a
// seed; buffers are fixed after construction (set_range_source stores one std::function).
//
// Behaviour emulated:
// - requests `A5 cmd [size payload xor]` (a bad xor gets no answer, as on the real unit): STOP,
//   RESET (reboot: silent for reset_ms, then the A2/A3 ASCII banner; an injected health error
//   clears), GET_INFO, GET_HEALTH, GET_SAMPLERATE (firmware >= 1.17), GET_LIDAR_CONF (firmware
//   >= 1.24 or new design: mode count, typical mode, per-mode answer type, us/sample, max
//   distance, name, desired rotation), GET_ACC_BOARD_FLAG (A2/A3: PWM board; C1: none),
//   SET_MOTOR_PWM, HQ_MOTOR_SPEED_CTRL, SCAN/FORCE_SCAN (standard nodes 0x81), EXPRESS_SCAN mode
//   0 (legacy capsules 0x82) and the model's dense mode (0x85). While scanning, only STOP, RESET,
//   scan and motor commands are obeyed (queries are ignored, as by the real unit).
// - the motor: an A1 spins only with DTR de-asserted (set_dtr(); Linux asserts it on open), an
//   A2/A3 only with PWM > 0, S-series and C1 on their own (an rpm command sets the S rate);
//   samples flow spin_up_ms after the motor started and a scan command was given.
// - per model (A1/A2/A3/S1/S2/C1) the DEVINFO, sample durations and scan-mode table below. Modes
//   are the ones this emulator can encode: Standard (0x81), Express (0x82, A series) and
//   DenseBoost (0x85, S/C series); ultra capsules (0x84) are decoded by the driver but not
//   produced here.
// - ranges per revolution from set_ranges() or a RangeSource callback (the simulator's ray
//   caster, or RecordedScans), in the SENSOR frame: beam i of N at lidar angle i * 360 / N deg,
//   clockwise seen from above; 0 or non-finite = no return.
// - faults: garbage bytes before data frames, corrupted data frames (a bit flipped inside a
//   capsule after its checksum was sealed, or a check bit of a standard node), total silence,
//   injected health error, revolution rate changes at run time.
#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "coxswain/core/time.hpp"
#include "coxswain/drivers/rplidar/protocol.hpp"
#include "sim/devices/device_emulator.hpp"

namespace coxswain::sim::devices::rplidar {

namespace proto = drivers::rplidar;

enum class Model : std::uint8_t { kA1, kA2, kA3, kS1, kS2, kC1 };
[[nodiscard]] std::string_view model_name(Model model);
/// "A1", "a2", ... -> Model.
[[nodiscard]] std::optional<Model> parse_model(std::string_view name);

/// One scan mode of the emulated unit (GET_LIDAR_CONF table).
struct ScanModeInfo {
  const char* name = "";
  proto::AnswerType answer = proto::AnswerType::kMeasurement;
  double us_per_sample = 500.0;
};

/// What a model looks like to the host.
struct ModelProfile {
  proto::DeviceInfo info;
  std::uint16_t standard_us = 500;  // GET_SAMPLERATE
  std::uint16_t express_us = 250;
  std::array<ScanModeInfo, 2> modes{};  // id 0 = Standard, id 1 = the express/dense mode
  std::uint16_t typical_mode = 1;
  float max_range_m = 12.0F;
  bool has_pwm_board = false;  // answers GET_ACC_BOARD_FLAG with bit0 set
  [[nodiscard]] bool supports_sample_rate() const;
  [[nodiscard]] bool supports_conf() const;
};
[[nodiscard]] ModelProfile model_profile(Model model);

struct EmulatorFaults {
  double garbage_probability = 0.0;  // per data frame: 1..16 random bytes sent before it
  double corrupt_probability = 0.0;  // per data frame: one bit flipped after sealing
  bool silent = false;               // sends nothing at all (dead unit, cut cable)
  std::uint64_t seed = 1;

  [[nodiscard]] std::optional<std::string> validate() const;
};

struct EmulatorConfig {
  Model model = Model::kA1;
  double revolution_hz = 10.0;  // A/C units; S units use the rpm command when given
  std::int64_t spin_up_ms = 300;
  std::int64_t reset_ms = 500;  // reboot time after RESET
  /// GET_HEALTH answer at power-on: 0 good, 1 warning, 2 error (protection stop: scans refused).
  std::uint8_t health_status = 0;
  std::uint16_t health_error_code = 0;
  bool health_error_clears_on_reset = true;
  EmulatorFaults faults{};

  [[nodiscard]] std::optional<std::string> validate() const;
};

struct EmulatorStats {
  std::uint64_t requests = 0;
  std::uint64_t bad_requests = 0;  // wrong checksum
  std::uint64_t ignored_requests = 0;
  std::uint64_t stops = 0;
  std::uint64_t resets = 0;
  std::uint64_t info_requests = 0;
  std::uint64_t health_requests = 0;
  std::uint64_t conf_requests = 0;
  std::uint64_t scans_started = 0;  // scan commands obeyed (any mode)
  std::uint64_t data_frames = 0;    // nodes or capsules sent
  std::uint64_t samples = 0;
  std::uint64_t revolutions = 0;
  std::uint64_t garbage_bursts = 0;
  std::uint64_t corrupted_frames = 0;
  std::uint64_t dropped_bytes = 0;  // output buffer full
  std::uint64_t skipped_samples = 0;
  std::uint16_t motor_pwm = 0;  // last SET_MOTOR_PWM
  std::uint16_t motor_rpm = 0;  // last HQ_MOTOR_SPEED_CTRL
};

class Emulator final : public DeviceEmulator {
 public:
  static constexpr std::size_t kMaxBeams = 8192;
  static constexpr std::size_t kOutputCapacity = 1 << 17;
  static constexpr std::size_t kInitialOutputBytes = 1 << 12;
  /// At most this many samples are produced per poll; older ones are skipped.
  static constexpr std::uint64_t kMaxSamplesPerPoll = 40000;

  /// Fills `ranges_m` (its size = the beams given to set_range_source) for revolution `n`.
  using RangeSource = std::function<void(std::uint64_t revolution, std::span<float> ranges_m)>;

  explicit Emulator(const EmulatorConfig& config = {});

  void receive(std::span<const std::uint8_t> host_bytes, core::TimeNs now_ns) override;
  [[nodiscard]] std::span<const std::uint8_t> poll(core::TimeNs now_ns) override;

  /// Ranges used from the next revolution on (clears any RangeSource). At most kMaxBeams.
  void set_ranges(std::span<const float> ranges_m);
  /// Asks `source` for `beams` ranges at the start of every revolution.
  void set_range_source(std::size_t beams, RangeSource source);
  /// The DTR modem line as the host drives it (A1 motor: spins only when de-asserted).
  void set_dtr(bool asserted) { dtr_asserted_ = asserted; }
  void set_revolution_hz(double hz);
  void set_faults(const EmulatorFaults& faults) { config_.faults = faults; }
  /// Injects (status 2 = error) or clears a health condition now.
  void set_health(std::uint8_t status, std::uint16_t error_code);

  [[nodiscard]] const EmulatorStats& stats() const { return stats_; }
  [[nodiscard]] const ModelProfile& profile() const { return profile_; }
  [[nodiscard]] bool scanning() const { return scan_ != ScanKind::kNone; }
  [[nodiscard]] bool motor_spinning() const;
  [[nodiscard]] double revolution_hz() const;
  [[nodiscard]] proto::AnswerType scan_answer() const;

 private:
  enum class ScanKind : std::uint8_t { kNone, kStandard, kExpress, kDense };
  enum class RxPhase : std::uint8_t { kSync, kCommand, kSize, kPayload, kChecksum };

  void on_request(std::uint8_t cmd, std::span<const std::uint8_t> payload, core::TimeNs now_ns);
  void answer_conf(std::span<const std::uint8_t> payload);
  void start_scan(ScanKind kind, core::TimeNs now_ns);
  void produce(core::TimeNs now_ns);
  void emit_sample(double angle_deg, float range_m, bool start);
  void emit_frame(std::span<std::uint8_t> frame, bool capsule);
  void put(std::span<const std::uint8_t> bytes);
  void new_revolution();
  [[nodiscard]] float range_at(double angle_deg) const;
  [[nodiscard]] double sample_us() const;
  [[nodiscard]] std::uint64_t next_random();
  [[nodiscard]] double uniform();

  EmulatorConfig config_;
  ModelProfile profile_;
  EmulatorStats stats_;
  std::uint64_t rng_state_;

  // Host request parser.
  RxPhase rx_phase_ = RxPhase::kSync;
  std::uint8_t rx_cmd_ = 0;
  std::uint8_t rx_size_ = 0;
  std::array<std::uint8_t, 255> rx_payload_{};
  std::size_t rx_len_ = 0;
  std::uint8_t rx_xor_ = 0;

  // Device state.
  bool dtr_asserted_ = false;
  std::uint16_t pwm_ = 0;
  std::uint16_t rpm_ = 0;
  double revolution_hz_;
  std::uint8_t health_status_;
  std::uint16_t health_code_;
  core::TimeNs rebooting_until_ns_ = core::kNeverNs;
  bool banner_pending_ = false;
  core::TimeNs motor_on_since_ns_ = core::kNeverNs;
  ScanKind scan_ = ScanKind::kNone;
  core::TimeNs next_sample_ns_ = core::kNeverNs;
  double sample_remainder_ns_ = 0.0;
  double angle_deg_ = 0.0;
  bool revolution_start_ = true;
  bool first_capsule_ = true;

  // Capsule being filled.
  std::array<std::uint16_t, 40> capsule_mm_{};
  std::size_t capsule_n_ = 0;
  double capsule_start_deg_ = 0.0;

  // Ranges.
  std::vector<float> ranges_;  // current revolution (size fixed by the last set_*)
  std::vector<float> pending_ranges_;
  bool have_pending_ = false;
  RangeSource source_;
  std::uint64_t revolution_ = 0;

  std::vector<std::uint8_t> out_;
  std::size_t out_len_ = 0;
  std::size_t returned_ = 0;
};

/// The source team's recorded scans (testdata peer/tricat221-0223-scans.jsonl, ROS LaserScan
/// in rplidar_ros's `laser` frame, theta_ros = pi - theta_raw) turned back into the lidar's own
/// angles: beam i of beams() at lidar angle i * 360 / beams() deg, clockwise. Null = no return.
class RecordedScans {
 public:
  /// Reads the JSON-lines file; nullopt (and `error`) when it cannot be read or has no scans.
  static std::optional<RecordedScans> load(const std::filesystem::path& path, std::string* error);

  [[nodiscard]] std::size_t size() const { return scans_.size(); }
  [[nodiscard]] std::size_t beams() const { return beams_; }
  [[nodiscard]] std::span<const float> scan(std::size_t i) const { return scans_[i]; }
  /// RangeSource body: revolution n plays scan n modulo size().
  void fill(std::uint64_t revolution, std::span<float> ranges_m) const;
  /// A RangeSource that plays these scans in a loop (copies the scans).
  [[nodiscard]] Emulator::RangeSource source() const;

 private:
  std::size_t beams_ = 0;
  std::vector<std::vector<float>> scans_;
};

}  // namespace coxswain::sim::devices::rplidar
