// SPDX-License-Identifier: Apache-2.0
#pragma once
// Who may talk to the live view: the Host and Origin checks against DNS rebinding and
// cross-site requests, the token carried in a request, and a rate limit for the warnings a
// refused request writes. Pure functions of the request's text; no I/O.
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace coxswain::live {

/// The host part of a Host header or an authority ("boat.local:8765" -> "boat.local",
/// "[::1]:8765" -> "::1"), lower-cased. Empty when malformed.
[[nodiscard]] std::string host_name_of(std::string_view authority);

/// True when `host` (as host_name_of returns it) is an IPv4 or IPv6 literal.
[[nodiscard]] bool is_ip_literal(std::string_view host);

/// A Host header names this server when its host is an IP literal (a rebinding attack needs a
/// name the attacker's DNS controls), "localhost", or one of `allowed_hosts`.
[[nodiscard]] bool host_allowed(std::string_view host_header,
                                const std::vector<std::string>& allowed_hosts);

/// A browser's Origin is allowed when absent (not a browser), same-origin ("http://" + the Host
/// header), or listed in `allowed_origins` (exact "scheme://host[:port]").
[[nodiscard]] bool origin_allowed(std::optional<std::string_view> origin,
                                  std::string_view host_header,
                                  const std::vector<std::string>& allowed_origins);

/// The target without its query ("/api/start?x=1" -> "/api/start").
[[nodiscard]] std::string_view path_of(std::string_view target);

/// The value of `token=` in the target's query, if any (not percent-decoded: tokens are meant
/// to be URL-safe).
[[nodiscard]] std::optional<std::string_view> query_token(std::string_view target);

/// At most one warning per `period` for a kind of refusal, counting the ones in between, so a
/// flood of refused requests writes a bounded log.
class WarningLimiter {
 public:
  using Clock = std::chrono::steady_clock;
  explicit WarningLimiter(Clock::duration period) : period_(period) {}
  /// True when this occurrence should be logged; `suppressed` is then how many were not since
  /// the last logged one.
  bool allow(Clock::time_point now, std::uint64_t& suppressed);

 private:
  Clock::duration period_;
  std::optional<Clock::time_point> last_;
  std::uint64_t suppressed_ = 0;
};

}  // namespace coxswain::live
