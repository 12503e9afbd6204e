// SPDX-License-Identifier: Apache-2.0
#include "coxswain/drivers/serial/serial_transport.hpp"

#include <linux/serial.h>
#include <spdlog/spdlog.h>
#include <sys/ioctl.h>
#include <termios.h>

#include <algorithm>
#include <atomic>
#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/serial_port.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/write.hpp>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

namespace coxswain::drivers::serial {
namespace asio = boost::asio;

namespace {

std::string describe_open_error(const std::string& path, const boost::system::error_code& ec) {
  if (path.empty()) return "no device path configured";
  std::string text = path + ": " + ec.message();
  std::error_code fs_ec;
  switch (ec.value()) {
    case ENOENT:
      if (std::filesystem::is_symlink(path, fs_ec)) {
        text += " (dangling link to " + std::filesystem::read_symlink(path, fs_ec).string() +
                ": device unplugged?)";
      } else {
        text += " (device not plugged in, or no udev rule names it?)";
      }
      break;
    case EACCES:
    case EPERM:
      text += " (is the user in the dialout group?)";
      break;
    case EBUSY:
      text += " (another program holds the port)";
      break;
    default:
      break;
  }
  return text;
}

}  // namespace

// Everything below runs on the transport's thread, except the constructor, start(), stop() and
// the atomic counters.
class SerialTransport::Impl final : public DeviceLink {
 public:
  Impl(const config::SerialDeviceConfig& config, DeviceSession& session,
       core::LatestSlot<msg::DeviceHealth>& health_slot, const core::Clock& clock,
       RawByteSink* raw_sink, const TransportOptions& options)
      : config_(config),
        session_(session),
        health_slot_(health_slot),
        clock_(clock),
        raw_sink_(raw_sink),
        options_(options),
        name_(msg::device_name(session.device())),
        port_(io_),
        tick_timer_(io_),
        reopen_timer_(io_),
        read_buf_(std::max<std::size_t>(1, options.read_chunk_bytes)),
        backoff_ns_(options.backoff_initial_ns) {
    queue_.reserve(options_.write_queue_bytes);
    inflight_.reserve(options_.write_queue_bytes);
    transport_detail_ = config_.path + ": not opened yet";
  }

  ~Impl() override { stop(); }

  void start() {
    if (thread_.joinable()) return;
    running_.store(true, std::memory_order_release);
    thread_ = std::thread([this] { run(); });
  }

  void stop() {
    if (!thread_.joinable()) return;
    asio::post(io_, [this] {
      stopping_ = true;
      close_port("stopped", /*publish=*/false);
      tick_timer_.cancel();
      reopen_timer_.cancel();
      io_.stop();
    });
    thread_.join();
    running_.store(false, std::memory_order_release);
  }

  [[nodiscard]] bool running() const { return running_.load(std::memory_order_acquire); }

  [[nodiscard]] TransportCounters counters() const {
    TransportCounters c;
    c.bytes_received = bytes_received_.load(std::memory_order_relaxed);
    c.bytes_written = bytes_written_.load(std::memory_order_relaxed);
    c.writes_dropped = writes_dropped_.load(std::memory_order_relaxed);
    c.bytes_dropped = bytes_dropped_.load(std::memory_order_relaxed);
    c.opens = opens_.load(std::memory_order_relaxed);
    c.reopen_count = reopen_count_.load(std::memory_order_relaxed);
    c.open_failures = open_failures_.load(std::memory_order_relaxed);
    c.closes = closes_.load(std::memory_order_relaxed);
    return c;
  }

  [[nodiscard]] msg::DeviceId device() const { return session_.device(); }

  // DeviceLink -------------------------------------------------------------------------------

  bool write(std::span<const std::uint8_t> bytes) override {
    if (bytes.empty()) return true;
    if (!open_ || queue_.size() + bytes.size() > options_.write_queue_bytes) {
      writes_dropped_.fetch_add(1, std::memory_order_relaxed);
      bytes_dropped_.fetch_add(bytes.size(), std::memory_order_relaxed);
      return false;
    }
    queue_.insert(queue_.end(), bytes.begin(), bytes.end());
    if (raw_sink_ != nullptr) {
      raw_sink_->on_raw(session_.device(), RawDirection::kToDevice, clock_.now_ns(), bytes);
    }
    if (!writing_) start_write();
    return true;
  }

  void set_dtr(bool asserted) override {
    if (!open_) return;
    int bits = TIOCM_DTR;
    if (::ioctl(port_.native_handle(), asserted ? TIOCMBIS : TIOCMBIC, &bits) != 0 &&
        !dtr_failure_logged_) {
      // A pseudo-terminal has no modem lines: expected with the simulator's emulators.
      dtr_failure_logged_ = true;
      spdlog::debug("{}: cannot set DTR on {}: {}", name_, config_.path, std::strerror(errno));
    }
  }

  void flush_input() override {
    if (open_) ::tcflush(port_.native_handle(), TCIFLUSH);
  }

 private:
  void run() {
    try_open();
    tick_timer_.expires_after(std::chrono::nanoseconds(options_.poll_period_ns));
    arm_tick();
    auto guard = asio::make_work_guard(io_);
    for (;;) {
      try {
        io_.run();
        return;
      } catch (const std::exception& e) {
        // Nothing should throw here; if a session does, keep the device alive rather than
        // losing it for the rest of the run.
        spdlog::error("{}: unexpected exception on the device thread: {}", name_, e.what());
      }
    }
  }

  void arm_tick() {
    tick_timer_.async_wait([this](const boost::system::error_code& ec) {
      if (ec || stopping_) return;
      on_tick();
      // Absolute period; after a stall, skip the missed polls instead of bursting through them.
      const auto period = std::chrono::nanoseconds(options_.poll_period_ns);
      auto next = tick_timer_.expiry() + period;
      const auto now = std::chrono::steady_clock::now();
      if (next < now) next = now + period;
      tick_timer_.expires_at(next);
      arm_tick();
    });
  }

  void on_tick() {
    const core::TimeNs now = clock_.now_ns();
    if (open_ && session_.on_poll(*this, now) == SessionVerdict::kReopen) {
      close_port("the session asked for a reopen", /*publish=*/true);
      schedule_reopen();
    }
    publish_health(now, /*force=*/false);
  }

  void try_open() {
    if (stopping_ || open_) return;
    set_transport_state(msg::DeviceState::kOpening, config_.path + ": opening");
    boost::system::error_code ec;
    if (config_.path.empty()) {
      ec = boost::system::errc::make_error_code(boost::system::errc::no_such_file_or_directory);
    } else {
      port_.open(config_.path, ec);
    }
    if (ec) {
      fail_open(msg::DeviceState::kAbsent, describe_open_error(config_.path, ec));
      return;
    }
    std::string why;
    if (!configure_port(why)) {
      port_.close(ec);
      fail_open(msg::DeviceState::kError, config_.path + ": " + why);
      return;
    }
    open_ = true;
    ++generation_;
    writing_ = false;
    queue_.clear();
    got_data_since_open_ = false;
    last_open_error_.clear();
    if (opens_.fetch_add(1, std::memory_order_relaxed) > 0) {
      reopen_count_.fetch_add(1, std::memory_order_relaxed);
    }
    spdlog::info("{}: opened {} at {} baud", name_, config_.path, config_.baud);
    const core::TimeNs now = clock_.now_ns();
    session_.on_open(*this, now);
    start_read();
    publish_health(now, /*force=*/true);
  }

  void fail_open(msg::DeviceState state, const std::string& detail) {
    open_failures_.fetch_add(1, std::memory_order_relaxed);
    if (detail != last_open_error_) {  // once per distinct reason, not every retry
      spdlog::warn("{}: cannot open: {}; retrying with backoff", name_, detail);
      last_open_error_ = detail;
    }
    set_transport_state(state, detail);
    schedule_reopen();
  }

  bool configure_port(std::string& why) {
    boost::system::error_code ec;
    using P = asio::serial_port_base;
    port_.set_option(P::baud_rate(config_.baud), ec);
    if (ec) {
      why = "baud " + std::to_string(config_.baud) + ": " + ec.message();
      return false;
    }
    port_.set_option(P::character_size(8), ec);
    if (!ec) port_.set_option(P::parity(P::parity::none), ec);
    if (!ec) port_.set_option(P::stop_bits(P::stop_bits::one), ec);
    if (!ec) port_.set_option(P::flow_control(P::flow_control::none), ec);
    if (ec) {
      why = "8N1 without flow control: " + ec.message();
      return false;
    }
    const int fd = port_.native_handle();
    // Asio leaves a few input/output processing flags alone; make the line fully raw.
    termios t{};
    if (::tcgetattr(fd, &t) == 0) {
      const speed_t in_speed = ::cfgetispeed(&t);
      const speed_t out_speed = ::cfgetospeed(&t);
      ::cfmakeraw(&t);
      t.c_cflag |= CLOCAL | CREAD;
      t.c_cc[VMIN] = 1;
      t.c_cc[VTIME] = 0;
      ::cfsetispeed(&t, in_speed);
      ::cfsetospeed(&t, out_speed);
      if (::tcsetattr(fd, TCSANOW, &t) != 0) {
        why = std::string("raw mode: ") + std::strerror(errno);
        return false;
      }
    }
    // FTDI/CP210x/CH340 adapters buffer up to 16 ms by default; low latency trades a little CPU
    // for timely stamps. Not every driver (nor a pty) supports it: that is fine.
    serial_struct ss{};
    if (::ioctl(fd, TIOCGSERIAL, &ss) == 0) {
      ss.flags = static_cast<int>(static_cast<unsigned>(ss.flags) | ASYNC_LOW_LATENCY);
      if (::ioctl(fd, TIOCSSERIAL, &ss) != 0) {
        spdlog::debug("{}: ASYNC_LOW_LATENCY refused: {}", name_, std::strerror(errno));
      }
    } else {
      spdlog::debug("{}: no serial_struct on {} (not a UART driver?)", name_, config_.path);
    }
    ::tcflush(fd, TCIFLUSH);  // bytes from before the open would carry wrong stamps
    return true;
  }

  void start_read() {
    const std::uint64_t gen = generation_;
    port_.async_read_some(
        asio::buffer(read_buf_),
        [this, gen](const boost::system::error_code& ec, std::size_t n) { on_read(ec, n, gen); });
  }

  void on_read(const boost::system::error_code& ec, std::size_t n, std::uint64_t gen) {
    if (gen != generation_ || stopping_) return;  // a port that has been closed since
    if (n > 0) {
      const core::TimeNs arrival_ns = clock_.now_ns();
      bytes_received_.fetch_add(n, std::memory_order_relaxed);
      const std::span<const std::uint8_t> bytes(read_buf_.data(), n);
      if (raw_sink_ != nullptr) {
        raw_sink_->on_raw(session_.device(), RawDirection::kFromDevice, arrival_ns, bytes);
      }
      if (!got_data_since_open_) {
        got_data_since_open_ = true;
        backoff_ns_ = options_.backoff_initial_ns;  // this device works again
      }
      session_.on_bytes(bytes, arrival_ns, *this);
    }
    if (ec) {
      // EOF or EIO: the USB device went away (or the pty's master closed).
      close_port("read failed: " + ec.message(), /*publish=*/true);
      schedule_reopen();
      return;
    }
    if (open_ && gen == generation_) start_read();
  }

  void start_write() {
    if (queue_.empty() || !open_) return;
    inflight_.swap(queue_);
    queue_.clear();
    writing_ = true;
    const std::uint64_t gen = generation_;
    asio::async_write(port_, asio::buffer(inflight_),
                      [this, gen](const boost::system::error_code& ec, std::size_t n) {
                        if (gen != generation_) return;
                        bytes_written_.fetch_add(n, std::memory_order_relaxed);
                        writing_ = false;
                        inflight_.clear();
                        // A write error means the device is going away: the read side sees it
                        // too and closes the port.
                        if (!ec) start_write();
                      });
  }

  void close_port(const std::string& why, bool publish) {
    if (!open_) return;
    open_ = false;
    ++generation_;
    boost::system::error_code ignored;
    port_.close(ignored);
    writing_ = false;
    queue_.clear();
    closes_.fetch_add(1, std::memory_order_relaxed);
    const core::TimeNs now = clock_.now_ns();
    session_.on_close(now);
    if (!publish) return;
    spdlog::warn("{}: closed {}: {}", name_, config_.path, why);
    std::error_code fs_ec;
    if (std::filesystem::exists(config_.path, fs_ec)) {
      set_transport_state(msg::DeviceState::kOpening, config_.path + ": " + why + "; reopening");
    } else {
      set_transport_state(msg::DeviceState::kAbsent,
                          config_.path + ": " + why + "; path gone (unplugged?)");
    }
  }

  void schedule_reopen() {
    if (stopping_) return;
    reopen_timer_.expires_after(std::chrono::nanoseconds(backoff_ns_));
    backoff_ns_ = std::min(backoff_ns_ * 2, options_.backoff_max_ns);
    reopen_timer_.async_wait([this](const boost::system::error_code& ec) {
      if (!ec) try_open();
    });
  }

  void set_transport_state(msg::DeviceState state, std::string detail) {
    transport_state_ = state;
    transport_detail_ = std::move(detail);
    publish_health(clock_.now_ns(), /*force=*/false);
  }

  void publish_health(core::TimeNs now, bool force) {
    msg::DeviceHealth h;
    session_.fill_health(h, now);
    h.stamp_ns = now;
    h.device = session_.device();
    h.bytes_received = bytes_received_.load(std::memory_order_relaxed);
    h.reopen_count = reopen_count_.load(std::memory_order_relaxed);
    if (!open_) {
      h.state = transport_state_;
      h.set_detail(transport_detail_);
    }
    const bool changed = h.state != last_state_ || h.detail_text() != last_detail_.data();
    if (!force && !changed && last_health_ns_ != core::kNeverNs &&
        now - last_health_ns_ < options_.health_period_ns) {
      return;
    }
    health_slot_.publish(h, now);
    last_state_ = h.state;
    last_detail_ = h.detail;
    last_health_ns_ = now;
  }

  const config::SerialDeviceConfig config_;
  DeviceSession& session_;
  core::LatestSlot<msg::DeviceHealth>& health_slot_;
  const core::Clock& clock_;
  RawByteSink* const raw_sink_;
  const TransportOptions options_;
  const std::string name_;

  asio::io_context io_;
  asio::serial_port port_;
  asio::steady_timer tick_timer_;
  asio::steady_timer reopen_timer_;
  std::vector<std::uint8_t> read_buf_;
  std::vector<std::uint8_t> queue_;     // accepted, waiting for the write in flight
  std::vector<std::uint8_t> inflight_;  // being written

  // Device-thread state.
  bool stopping_ = false;
  bool open_ = false;
  bool writing_ = false;
  bool got_data_since_open_ = false;
  bool dtr_failure_logged_ = false;
  std::uint64_t generation_ = 0;  // bumped at each open/close: stale completions are ignored
  core::TimeNs backoff_ns_;
  msg::DeviceState transport_state_ = msg::DeviceState::kOpening;
  std::string transport_detail_;
  std::string last_open_error_;
  msg::DeviceState last_state_ = msg::DeviceState::kDisabled;
  std::array<char, 192> last_detail_{};
  core::TimeNs last_health_ns_ = core::kNeverNs;

  std::atomic<std::uint64_t> bytes_received_{0};
  std::atomic<std::uint64_t> bytes_written_{0};
  std::atomic<std::uint64_t> writes_dropped_{0};
  std::atomic<std::uint64_t> bytes_dropped_{0};
  std::atomic<std::uint64_t> opens_{0};
  std::atomic<std::uint32_t> reopen_count_{0};
  std::atomic<std::uint64_t> open_failures_{0};
  std::atomic<std::uint64_t> closes_{0};
  std::atomic<bool> running_{false};

  std::thread thread_;
};

SerialTransport::SerialTransport(const config::SerialDeviceConfig& config, DeviceSession& session,
                                 core::LatestSlot<msg::DeviceHealth>& health_slot,
                                 const core::Clock& clock, RawByteSink* raw_sink,
                                 const TransportOptions& options)
    : impl_(std::make_unique<Impl>(config, session, health_slot, clock, raw_sink, options)) {}

SerialTransport::~SerialTransport() = default;

void SerialTransport::start() { impl_->start(); }
void SerialTransport::stop() { impl_->stop(); }
bool SerialTransport::running() const { return impl_->running(); }
TransportCounters SerialTransport::counters() const { return impl_->counters(); }
msg::DeviceId SerialTransport::device() const { return impl_->device(); }

}  // namespace coxswain::drivers::serial
