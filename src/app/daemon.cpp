// SPDX-License-Identifier: Apache-2.0
#include "coxswain/app/daemon.hpp"

#include <signal.h>
#include <spdlog/spdlog.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <thread>

#include "coxswain/app/device_probe.hpp"
#include "coxswain/app/device_sessions.hpp"
#include "coxswain/app/health_reporter.hpp"
#include "coxswain/app/raw_capture_sink.hpp"
#include "coxswain/app/serial_drivers.hpp"
#include "coxswain/app/systemd_notify.hpp"
#include "coxswain/app/tick_loop.hpp"
#include "coxswain/core/clock.hpp"
#include "coxswain/core/latest_store.hpp"

namespace coxswain::app {
namespace {

constexpr core::TimeNs kProbePeriodNs = core::kNsPerSec;
constexpr core::TimeNs kCountersPeriodNs = 10 * core::kNsPerSec;

msg::ActuatorCommand neutral_command(const config::BoatConfig& boat, core::TimeNs now_ns) {
  msg::ActuatorCommand cmd;
  cmd.stamp_ns = now_ns;
  cmd.active = false;
  if (boat.actuators.layout == msg::ActuatorLayout::kServoThruster) {
    cmd.pulse_us = {boat.actuators.servo.center_us, boat.actuators.thruster.neutral_us};
  } else {
    cmd.pulse_us = {boat.actuators.thruster.neutral_us, boat.actuators.thruster.neutral_us};
  }
  return cmd;
}

// Waits for SIGINT/SIGTERM on its own thread (the signals are blocked everywhere else), so the
// stop request is handled in ordinary code rather than in a signal handler.
class SignalWaiter {
 public:
  explicit SignalWaiter(TickLoop& loop) : loop_(loop) {
    thread_ = std::thread([this] { wait(); });
  }
  ~SignalWaiter() {
    done_.store(true);
    thread_.join();
  }
  SignalWaiter(const SignalWaiter&) = delete;
  SignalWaiter& operator=(const SignalWaiter&) = delete;
  [[nodiscard]] int signal_number() const { return signal_.load(); }

 private:
  void wait() {
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, SIGINT);
    sigaddset(&set, SIGTERM);
    const timespec poll{0, 100'000'000};
    while (!done_.load()) {
      const int sig = sigtimedwait(&set, nullptr, &poll);
      if (sig > 0) {
        signal_.store(sig);
        loop_.request_stop();
        return;
      }
    }
  }
  TickLoop& loop_;
  std::atomic<bool> done_{false};
  std::atomic<int> signal_{0};
  std::thread thread_;
};

// Probes device presence once a second until stopped (see DeviceProbe).
class ProbeThread {
 public:
  ProbeThread(DeviceProbe& probe, const core::Clock& clock) : probe_(probe), clock_(clock) {
    probe_.probe_once(clock_.now_ns());  // the first tick already sees every device's state
    thread_ = std::thread([this] { run(); });
  }
  ~ProbeThread() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    thread_.join();
  }
  ProbeThread(const ProbeThread&) = delete;
  ProbeThread& operator=(const ProbeThread&) = delete;

 private:
  void run() {
    std::unique_lock<std::mutex> lock(mutex_);
    while (
        !wake_.wait_for(lock, std::chrono::nanoseconds(kProbePeriodNs), [this] { return stop_; })) {
      probe_.probe_once(clock_.now_ns());
    }
  }
  DeviceProbe& probe_;
  const core::Clock& clock_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  std::thread thread_;
};

}  // namespace

void block_stop_signals() {
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);
}

int run_daemon(const config::Configuration& config, const RunOptions& options) {
  block_stop_signals();  // idempotent; the caller should already have done it before its threads

  const core::SteadyClock clock;
  const SystemdNotifier notifier;
  auto store = std::make_unique<core::LatestStore>();
  auto snapshot = std::make_unique<core::Snapshot>();
  HealthReporter reporter;

  std::unique_ptr<RawCaptureSink> capture;
  if (!options.capture_dir.empty()) {
    capture = std::make_unique<RawCaptureSink>(options.capture_dir);
    spdlog::info("capture mode: raw device bytes go to {}/<device>.raw",
                 options.capture_dir.string());
  }
  // The recorder's raw hook will go here too; for now only capture mode takes the bytes.
  drivers::RawByteSink* const raw_sink = capture.get();
  SerialDrivers serial_drivers(
      config.devices, [&](msg::DeviceId id) { return make_device_session(id, config, *store); },
      *store, clock, raw_sink);
  // Devices with a driver publish their own health; the probe watches only the others.
  DeviceProbe probe(config.devices, *store, serial_drivers.driven());

  TickLoop loop(clock, &TickLoop::sleep_until_steady,
                TickLoop::Params{config.mission.tick_rate_hz, kCountersPeriodNs});
  spdlog::info("mission '{}' from {}; tick {:.1f} Hz; run directory {}", config.mission.name,
               config.mission.file, config.mission.tick_rate_hz, options.run_dir.string());
  spdlog::info("no mission core in this build: the boat holds neutral outputs while the loop runs");

  SignalWaiter signals(loop);
  ProbeThread probe_thread(probe, clock);
  serial_drivers.start();

  const core::TimeNs start_ns = clock.now_ns();
  const core::TimeNs stop_at_ns =
      options.run_for_s > 0.0 ? start_ns + core::sec_to_ns(options.run_for_s) : INT64_MAX;
  const core::TimeNs watchdog_every_ns = notifier.watchdog_interval_ns() / 2;
  core::TimeNs last_watchdog_ns = core::kNeverNs;
  core::TimeNs next_counters_ns = start_ns + kCountersPeriodNs;

  notifier.ready();
  notifier.status("running: " + config.mission.name);

  loop.run(
      [&](const TickInfo& tick) {
        store->snapshot(*snapshot);
        if (reporter.report_changes(*snapshot) > 0) {
          notifier.status(config.mission.name + ": " + HealthReporter::summary(*snapshot));
        }
        store->command.publish(neutral_command(config.boat, tick.now_ns), tick.now_ns);
        if (watchdog_every_ns > 0 && (last_watchdog_ns == core::kNeverNs ||
                                      tick.now_ns - last_watchdog_ns >= watchdog_every_ns)) {
          notifier.watchdog();  // fed from the tick: a stuck tick means systemd restarts us
          last_watchdog_ns = tick.now_ns;
        }
        if (tick.now_ns >= next_counters_ns) {
          reporter.report_counters(*snapshot, tick.now_ns);
          next_counters_ns += kCountersPeriodNs;
        }
        return tick.now_ns < stop_at_ns;
      },
      [](const TickWindowStats& s) {
        spdlog::info(
            "tick: {} ticks, duration min {:.3f} mean {:.3f} p99 {:.3f} max {:.3f} ms, "
            "max lateness {:.3f} ms, overruns {}, skipped {}",
            s.ticks, static_cast<double>(s.min_ns) * 1e-6, static_cast<double>(s.mean_ns) * 1e-6,
            static_cast<double>(s.p99_ns) * 1e-6, static_cast<double>(s.max_ns) * 1e-6,
            static_cast<double>(s.max_lateness_ns) * 1e-6, s.overruns, s.skipped_ticks);
      });

  notifier.stopping();
  if (serial_drivers.drives(msg::DeviceId::kArduino)) {
    // Give the Arduino driver two of its command periods to send neutral outputs before its
    // port closes (the board's own failsafe would neutralise them too, but later).
    const core::TimeNs now_ns = clock.now_ns();
    store->command.publish(neutral_command(config.boat, now_ns), now_ns);
    std::this_thread::sleep_for(
        std::chrono::nanoseconds(core::sec_to_ns(2.0 / config.boat.actuators.command_rate_hz)));
  }
  serial_drivers.stop();  // each returns within milliseconds, whatever its device does
  const core::TimeNs end_ns = clock.now_ns();
  store->command.publish(neutral_command(config.boat, end_ns), end_ns);
  if (capture) capture->stop();  // after the transports: they were its producers
  const int sig = signals.signal_number();
  spdlog::info("stopping{}: commanded neutral actuators; {} ticks in {:.1f} s, {} overruns",
               sig != 0 ? (sig == SIGINT ? " on SIGINT" : " on SIGTERM") : "", loop.total_ticks(),
               core::ns_to_sec(end_ns - start_ns), loop.total_overruns());
  return 0;
}

}  // namespace coxswain::app
