// SPDX-License-Identifier: Apache-2.0
#include "coxswain/live/request_guard.hpp"

#include <arpa/inet.h>

#include <algorithm>
#include <array>
#include <cctype>

namespace coxswain::live {

std::string host_name_of(std::string_view authority) {
  std::string_view host;
  if (!authority.empty() && authority.front() == '[') {
    const std::size_t close = authority.find(']');
    if (close == std::string_view::npos) return {};
    host = authority.substr(1, close - 1);
    const std::string_view rest = authority.substr(close + 1);
    if (!rest.empty() && rest.front() != ':') return {};
  } else {
    const std::size_t colon = authority.find(':');
    if (colon != std::string_view::npos &&
        authority.find(':', colon + 1) != std::string_view::npos) {
      return {};  // a bare IPv6 address is not a valid Host header
    }
    host = authority.substr(0, colon);
  }
  if (host.empty() || host.size() > 253) return {};
  std::string out;
  out.reserve(host.size());
  for (const char c : host) {
    const auto u = static_cast<unsigned char>(c);
    if (std::isalnum(u) == 0 && c != '.' && c != '-' && c != ':' && c != '_') return {};
    out.push_back(static_cast<char>(std::tolower(u)));
  }
  if (out.back() == '.') out.pop_back();  // "localhost." names the same host
  return out;
}

bool is_ip_literal(std::string_view host) {
  if (host.empty() || host.size() >= 64) return false;
  const std::string s(host);
  std::array<unsigned char, 16> buf{};
  return ::inet_pton(AF_INET, s.c_str(), buf.data()) == 1 ||
         ::inet_pton(AF_INET6, s.c_str(), buf.data()) == 1;
}

bool host_allowed(std::string_view host_header, const std::vector<std::string>& allowed_hosts) {
  const std::string host = host_name_of(host_header);
  if (host.empty()) return false;
  if (is_ip_literal(host) || host == "localhost") return true;
  return std::any_of(allowed_hosts.begin(), allowed_hosts.end(),
                     [&](const std::string& a) { return host_name_of(a) == host; });
}

bool origin_allowed(std::optional<std::string_view> origin, std::string_view host_header,
                    const std::vector<std::string>& allowed_origins) {
  if (!origin) return true;
  std::string lower(*origin);
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (!host_header.empty()) {
    std::string same = "http://";
    for (const char c : host_header) {
      same.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
    }
    if (lower == same) return true;
  }
  return std::any_of(allowed_origins.begin(), allowed_origins.end(), [&](const std::string& a) {
    if (a.size() != lower.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i) {
      if (std::tolower(static_cast<unsigned char>(a[i])) != lower[i]) return false;
    }
    return true;
  });
}

std::string_view path_of(std::string_view target) {
  return target.substr(0, target.find_first_of("?#"));
}

std::optional<std::string_view> query_token(std::string_view target) {
  const std::size_t q = target.find('?');
  if (q == std::string_view::npos) return std::nullopt;
  std::string_view query = target.substr(q + 1);
  query = query.substr(0, query.find('#'));
  while (!query.empty()) {
    const std::size_t amp = query.find('&');
    const std::string_view pair = query.substr(0, amp);
    if (pair.starts_with("token=")) return pair.substr(6);
    if (amp == std::string_view::npos) break;
    query.remove_prefix(amp + 1);
  }
  return std::nullopt;
}

bool WarningLimiter::allow(Clock::time_point now, std::uint64_t& suppressed) {
  if (last_ && now - *last_ < period_) {
    ++suppressed_;
    return false;
  }
  last_ = now;
  suppressed = suppressed_;
  suppressed_ = 0;
  return true;
}

}  // namespace coxswain::live
