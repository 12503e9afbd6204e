// SPDX-License-Identifier: Apache-2.0
#include "coxswain/drivers/ublox/rtcm_source.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <boost/asio/connect.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/posix/stream_descriptor.hpp>
#include <boost/asio/steady_timer.hpp>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <span>
#include <utility>

#include "coxswain/drivers/ublox/codec.hpp"

namespace coxswain::drivers::ublox {

namespace asio = boost::asio;
using boost::system::error_code;

struct RtcmSource::Impl {
  Impl(RtcmQueue& q, const RtcmSourceOptions& o)
      : queue(q), options(o), socket(io), resolver(io), pipe(io), timer(io) {}

  RtcmQueue& queue;
  RtcmSourceOptions options;
  asio::io_context io;
  asio::ip::tcp::socket socket;
  asio::ip::tcp::resolver resolver;
  asio::posix::stream_descriptor pipe;
  asio::steady_timer timer;
  std::array<std::uint8_t, 4096> buf{};
  Rtcm3Framer framer;
  core::TimeNs backoff_ns = 0;
  std::string host, port, path;
  std::atomic<bool> stopping{false};

  std::atomic<std::uint64_t> bytes_in{0}, frames_ok{0}, frames_queued{0}, frames_dropped{0},
      crc_errors{0}, framing_errors{0}, connects{0}, failures{0};
  std::atomic<bool> finished{false};
  std::string last_problem;  // reader thread only

  void problem(const std::string& what) {
    if (what == last_problem) return;  // once per distinct reason, not at every retry
    last_problem = what;
    if (options.on_event) options.on_event(true, what);
  }
  void recovered(const std::string& what) {
    if (last_problem.empty()) return;
    last_problem.clear();
    if (options.on_event) options.on_event(false, what);
  }
  [[nodiscard]] std::string address() const { return host + ":" + port; }

  /// Frames `bytes`; `wait_for_room`: block (politely) while the queue is full instead of
  /// dropping (a file has no deadline).
  void feed(std::span<const std::uint8_t> bytes, bool wait_for_room) {
    bytes_in.fetch_add(bytes.size(), std::memory_order_relaxed);
    while (!bytes.empty()) {
      const DecodeStep step = framer.decode(bytes);
      bytes = bytes.subspan(step.consumed);
      if (!step.produced) continue;
      frames_ok.fetch_add(1, std::memory_order_relaxed);
      const auto frame = framer.frame().bytes;
      bool queued = queue.push(frame);
      while (!queued && wait_for_room && !stopping.load(std::memory_order_acquire)) {
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
        queued = queue.push(frame);
      }
      (queued ? frames_queued : frames_dropped).fetch_add(1, std::memory_order_relaxed);
    }
    crc_errors.store(framer.stats().checksum_errors, std::memory_order_relaxed);
    framing_errors.store(framer.stats().framing_errors, std::memory_order_relaxed);
  }

  void retry_later(void (Impl::*again)()) {
    failures.fetch_add(1, std::memory_order_relaxed);
    framer.reset();  // a partial frame from the old connection never completes
    backoff_ns = backoff_ns == 0 ? options.backoff_initial_ns
                                 : std::min(backoff_ns * 2, options.backoff_max_ns);
    timer.expires_after(std::chrono::nanoseconds(backoff_ns));
    timer.async_wait([this, again](const error_code& ec) {
      if (!ec && !stopping.load(std::memory_order_acquire)) (this->*again)();
    });
  }

  // ---- TCP ----
  void tcp_connect() {
    resolver.async_resolve(host, port, [this](const error_code& ec, const auto& results) {
      if (ec) {
        problem("cannot resolve " + address() + ": " + ec.message() + "; retrying");
        return retry_later(&Impl::tcp_connect);
      }
      asio::async_connect(socket, results, [this](const error_code& ec2, const auto&) {
        if (ec2) {
          error_code ignored;
          socket.close(ignored);
          problem("cannot connect to " + address() + ": " + ec2.message() + "; retrying");
          return retry_later(&Impl::tcp_connect);
        }
        recovered("connected to " + address());
        connects.fetch_add(1, std::memory_order_relaxed);
        backoff_ns = 0;
        tcp_read();
      });
    });
  }
  void tcp_read() {
    socket.async_read_some(asio::buffer(buf), [this](const error_code& ec, std::size_t n) {
      if (ec) {  // includes EOF: the server went away
        error_code ignored;
        socket.close(ignored);
        problem("the connection to " + address() + " ended: " + ec.message() + "; reconnecting");
        return retry_later(&Impl::tcp_connect);
      }
      feed({buf.data(), n}, false);
      tcp_read();
    });
  }

  // ---- named pipe ----
  void pipe_open() {
    // Non-blocking so that opening never waits for a writer; a missing writer reads as EOF and
    // is retried after the backoff.
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) {
      problem("cannot open " + path + ": " + std::strerror(errno) + "; retrying");
      return retry_later(&Impl::pipe_open);
    }
    recovered("opened " + path);
    pipe.assign(fd);
    connects.fetch_add(1, std::memory_order_relaxed);
    pipe_read();
  }
  void pipe_read() {
    pipe.async_read_some(asio::buffer(buf), [this](const error_code& ec, std::size_t n) {
      if (ec) {
        error_code ignored;
        pipe.close(ignored);
        return retry_later(&Impl::pipe_open);
      }
      backoff_ns = 0;
      feed({buf.data(), n}, false);
      pipe_read();
    });
  }

  // ---- regular file ----
  void read_file() {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) {
      problem("cannot open " + path + ": " + std::strerror(errno));
      failures.fetch_add(1, std::memory_order_relaxed);
      finished.store(true, std::memory_order_release);
      return;
    }
    connects.fetch_add(1, std::memory_order_relaxed);
    while (!stopping.load(std::memory_order_acquire)) {
      const ssize_t n = ::read(fd, buf.data(), buf.size());
      if (n <= 0) break;
      feed({buf.data(), static_cast<std::size_t>(n)}, true);
    }
    ::close(fd);
    finished.store(true, std::memory_order_release);
  }
};

bool RtcmSource::parse_tcp(const std::string& input, std::string& host, std::string& port) {
  constexpr std::string_view kScheme = "tcp://";
  if (input.rfind(kScheme, 0) != 0) return false;
  const std::string rest = input.substr(kScheme.size());
  const auto colon = rest.rfind(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == rest.size()) return false;
  host = rest.substr(0, colon);
  port = rest.substr(colon + 1);
  if (host.size() > 2 && host.front() == '[' && host.back() == ']') {
    host = host.substr(1, host.size() - 2);  // [::1]:2101
  }
  return std::all_of(port.begin(), port.end(), [](char c) { return c >= '0' && c <= '9'; });
}

RtcmSource::RtcmSource(std::string input, RtcmQueue& queue, const RtcmSourceOptions& options)
    : input_(std::move(input)), queue_(queue), options_(options) {}

RtcmSource::~RtcmSource() { stop(); }

void RtcmSource::start() {
  if (input_.empty() || thread_.joinable()) return;
  impl_ = std::make_unique<Impl>(queue_, options_);
  Impl* impl = impl_.get();
  if (parse_tcp(input_, impl->host, impl->port)) {
    thread_ = std::thread([impl] {
      impl->tcp_connect();
      impl->io.run();
    });
    return;
  }
  impl->path = input_;
  struct stat st {};
  const bool is_fifo = ::stat(input_.c_str(), &st) == 0 && S_ISFIFO(st.st_mode);
  if (is_fifo) {
    thread_ = std::thread([impl] {
      impl->pipe_open();
      impl->io.run();
    });
  } else {
    thread_ = std::thread([impl] { impl->read_file(); });
  }
}

void RtcmSource::stop() {
  if (!impl_) return;
  impl_->stopping.store(true, std::memory_order_release);
  impl_->io.stop();
  if (thread_.joinable()) thread_.join();
}

RtcmSourceStats RtcmSource::stats() const {
  RtcmSourceStats s;
  if (!impl_) return s;
  const Impl& i = *impl_;
  s.bytes_in = i.bytes_in.load(std::memory_order_relaxed);
  s.frames_ok = i.frames_ok.load(std::memory_order_relaxed);
  s.frames_queued = i.frames_queued.load(std::memory_order_relaxed);
  s.frames_dropped = i.frames_dropped.load(std::memory_order_relaxed);
  s.crc_errors = i.crc_errors.load(std::memory_order_relaxed);
  s.framing_errors = i.framing_errors.load(std::memory_order_relaxed);
  s.connects = i.connects.load(std::memory_order_relaxed);
  s.failures = i.failures.load(std::memory_order_relaxed);
  s.finished = i.finished.load(std::memory_order_acquire);
  return s;
}

}  // namespace coxswain::drivers::ublox
