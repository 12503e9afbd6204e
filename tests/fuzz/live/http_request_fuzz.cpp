// SPDX-License-Identifier: Apache-2.0
// libFuzzer target for HTTP request parsing as the live server does it: Boost.Beast's request
// parser with the server's header and body limits, fed in chunks, then the request guard (Host,
// Origin, token in the query, path) on whatever was parsed. Contract: no crash, and the guard's
// answers are consistent (a host it allows has a name; a path has no query).
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

#include "coxswain/live/request_guard.hpp"

namespace http = boost::beast::http;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace coxswain::live;
  if (size == 0) return 0;
  const std::size_t chunk = 1 + data[0] % 64U;
  http::request_parser<http::string_body> parser;
  parser.header_limit(8192);
  parser.body_limit(8192);
  parser.eager(true);
  boost::beast::error_code ec;
  std::size_t off = 1;
  std::string pending;
  while (off < size && !parser.is_done()) {
    const std::size_t n = std::min(chunk, size - off);
    pending.append(reinterpret_cast<const char*>(data) + off, n);
    off += n;
    const std::size_t used = parser.put(boost::asio::buffer(pending), ec);
    if (ec == http::error::need_more) {
      ec = {};
    } else if (ec) {
      return 0;
    }
    pending.erase(0, used);
  }
  if (!parser.is_header_done()) return 0;
  const auto& req = parser.get();
  const std::string_view target(req.target().data(), req.target().size());
  if (path_of(target).find('?') != std::string_view::npos) std::abort();
  (void)query_token(target);
  const auto host_it = req.find(http::field::host);
  const std::string_view host =
      host_it == req.end() ? std::string_view()
                           : std::string_view(host_it->value().data(), host_it->value().size());
  if (host_allowed(host, {"boat.local"}) && host_name_of(host).empty()) std::abort();
  const auto origin_it = req.find(http::field::origin);
  if (origin_it != req.end()) {
    (void)origin_allowed(std::string_view(origin_it->value().data(), origin_it->value().size()),
                         host, {"https://app.foxglove.dev"});
  }
  return 0;
}
