// SPDX-License-Identifier: Apache-2.0
#pragma once
// Checks of the addresses, paths and URLs in the config files that `check-config` can make
// without opening anything: each returns why a value is wrong, or nullopt when it is fine, so the
// loaders can report it with file:line like any other config error.
#include <optional>
#include <string>
#include <string_view>

namespace coxswain::config {

/// `devices.gnss.rtcm_input`: "" (none), `tcp://HOST:PORT` (HOST a name, an IPv4 address or a
/// bracketed IPv6 address; PORT 1..65535), or a file or named-pipe path. Any other scheme
/// ("ntrip://", "http://", a `tcp://` without a port) is an error, not a file name.
[[nodiscard]] std::optional<std::string> validate_rtcm_input(std::string_view value);

/// `live.http_address`: an IPv4 or IPv6 address to bind (a name is not resolved at start-up).
[[nodiscard]] std::optional<std::string> validate_http_address(std::string_view value);

/// `live.control_socket`: "" (the run directory's) or a path that fits a Unix socket address
/// (at most 107 bytes) and names a file, not a directory.
[[nodiscard]] std::optional<std::string> validate_control_socket(std::string_view value);

/// A serial device path (`devices.*.port`): absolute, no NUL, not a directory name.
[[nodiscard]] std::optional<std::string> validate_device_path(std::string_view value);

/// `live.token`: "" (control disabled) or at least 12 URL-safe characters (A-Z a-z 0-9 - . _ ~),
/// because Foxglove clients pass it in the URL unescaped.
[[nodiscard]] std::optional<std::string> validate_live_token(std::string_view value);

/// One of `live.allowed_hosts` (a host name) or `live.allowed_origins` ("http[s]://host[:port]").
[[nodiscard]] std::optional<std::string> validate_allowed_host(std::string_view value);
[[nodiscard]] std::optional<std::string> validate_allowed_origin(std::string_view value);

}  // namespace coxswain::config
