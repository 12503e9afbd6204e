// SPDX-License-Identifier: Apache-2.0
#include "coxswain/config/input_checks.hpp"

#include <arpa/inet.h>

#include <array>
#include <cctype>
#include <charconv>

namespace coxswain::config {
namespace {

constexpr std::size_t kSunPathBytes = 108;  // sizeof(sockaddr_un::sun_path) on Linux

bool is_ipv4(std::string_view s) {
  if (s.empty() || s.size() > 15) return false;
  const std::string z(s);
  std::array<unsigned char, 4> buf{};
  return ::inet_pton(AF_INET, z.c_str(), buf.data()) == 1;
}

bool is_ipv6(std::string_view s) {
  if (s.empty() || s.size() > 45) return false;
  const std::string z(s);
  std::array<unsigned char, 16> buf{};
  return ::inet_pton(AF_INET6, z.c_str(), buf.data()) == 1;
}

// RFC 1123 host name: labels of letters, digits and '-', not starting or ending with '-'.
bool is_host_name(std::string_view s) {
  if (s.empty() || s.size() > 253) return false;
  std::size_t label = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const char c = s[i];
    if (c == '.') {
      if (label == 0 || s[i - 1] == '-') return false;
      label = 0;
      continue;
    }
    if (std::isalnum(static_cast<unsigned char>(c)) == 0 && c != '-') return false;
    if (c == '-' && label == 0) return false;
    if (++label > 63) return false;
  }
  return label > 0 && s.back() != '-';
}

std::optional<std::string> check_host_port(std::string_view authority, bool port_required) {
  std::string_view host;
  std::string_view port;
  if (!authority.empty() && authority.front() == '[') {
    const std::size_t close = authority.find(']');
    if (close == std::string_view::npos) return "an IPv6 address must be closed with ']'";
    host = authority.substr(1, close - 1);
    if (!is_ipv6(host)) return "'" + std::string(host) + "' is not an IPv6 address";
    const std::string_view rest = authority.substr(close + 1);
    if (!rest.empty()) {
      if (rest.front() != ':') return "expected ':PORT' after ']'";
      port = rest.substr(1);
    }
  } else {
    const std::size_t colon = authority.rfind(':');
    host = authority.substr(0, colon);
    if (colon != std::string_view::npos) port = authority.substr(colon + 1);
    if (host.find(':') != std::string_view::npos) {
      return "an IPv6 address must be written in brackets, e.g. [::1]:2101";
    }
    if (!is_ipv4(host) && !is_host_name(host)) {
      return "'" + std::string(host) + "' is not a host name or address";
    }
    if (colon == std::string_view::npos && port_required) return "a port is required (HOST:PORT)";
  }
  if (port_required && port.empty()) return "a port is required (HOST:PORT)";
  if (!port.empty()) {
    unsigned value = 0;
    const auto [end, ec] = std::from_chars(port.data(), port.data() + port.size(), value);
    if (ec != std::errc() || end != port.data() + port.size() || value == 0 || value > 65535) {
      return "port '" + std::string(port) + "' is not 1..65535";
    }
  }
  return std::nullopt;
}

}  // namespace

std::optional<std::string> validate_rtcm_input(std::string_view value) {
  if (value.empty()) return std::nullopt;
  if (value.find('\0') != std::string_view::npos) return "contains a NUL byte";
  const std::size_t scheme_end = value.find("://");
  if (scheme_end != std::string_view::npos) {
    const std::string_view scheme = value.substr(0, scheme_end);
    if (scheme != "tcp") {
      return "scheme '" + std::string(scheme) +
             "://' is not supported: use tcp://HOST:PORT (e.g. from str2str) or a file or pipe "
             "path";
    }
    const std::string_view authority = value.substr(scheme_end + 3);
    if (authority.find('/') != std::string_view::npos) {
      return "tcp://HOST:PORT takes no path (an NTRIP mount point needs str2str in between)";
    }
    if (const auto why = check_host_port(authority, true)) return "tcp input: " + *why;
    return std::nullopt;
  }
  if (value.back() == '/') return "names a directory, not a file or pipe";
  if (value.size() >= 4096) return "path longer than 4095 bytes";
  return std::nullopt;
}

std::optional<std::string> validate_http_address(std::string_view value) {
  if (is_ipv4(value) || is_ipv6(value)) return std::nullopt;
  return "'" + std::string(value) +
         "' is not an IP address (127.0.0.1 for this computer only, 0.0.0.0 for every interface)";
}

std::optional<std::string> validate_control_socket(std::string_view value) {
  if (value.empty()) return std::nullopt;
  if (value.find('\0') != std::string_view::npos) return "contains a NUL byte";
  if (value.back() == '/') return "names a directory, not a socket file";
  if (value.size() >= kSunPathBytes) {
    return "is " + std::to_string(value.size()) + " bytes; a Unix socket path has at most " +
           std::to_string(kSunPathBytes - 1);
  }
  return std::nullopt;
}

std::optional<std::string> validate_device_path(std::string_view value) {
  if (value.empty()) return "is empty";
  if (value.find('\0') != std::string_view::npos) return "contains a NUL byte";
  if (value.front() != '/') return "must be an absolute path such as /dev/ttyUSB0";
  if (value.back() == '/') return "names a directory, not a device";
  return std::nullopt;
}

std::optional<std::string> validate_live_token(std::string_view value) {
  if (value.empty()) return std::nullopt;
  for (const char c : value) {
    if (std::isalnum(static_cast<unsigned char>(c)) == 0 && c != '-' && c != '.' && c != '_' &&
        c != '~') {
      return "may hold only A-Z a-z 0-9 - . _ ~ (it is passed in a URL)";
    }
  }
  if (value.size() < 12) return "is shorter than 12 characters";
  return std::nullopt;
}

std::optional<std::string> validate_allowed_host(std::string_view value) {
  if (is_host_name(value) || is_ipv4(value)) return std::nullopt;
  return "'" + std::string(value) + "' is not a host name";
}

std::optional<std::string> validate_allowed_origin(std::string_view value) {
  std::string_view rest;
  if (value.starts_with("http://")) {
    rest = value.substr(7);
  } else if (value.starts_with("https://")) {
    rest = value.substr(8);
  } else {
    return "must start with http:// or https://";
  }
  if (rest.empty() || rest.find('/') != std::string_view::npos) {
    return "must be scheme://host[:port] with no path";
  }
  if (const auto why = check_host_port(rest, false)) return *why;
  return std::nullopt;
}

}  // namespace coxswain::config
