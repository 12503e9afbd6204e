// SPDX-License-Identifier: Apache-2.0
// libFuzzer target for WebSocket frame parsing as the live server does it: a server-side
// Boost.Beast stream accepts a valid upgrade request, then reads the input as frames from the
// client (with the server's message limit), answering pings and closes on an in-memory stream.
// Contract: no crash; messages larger than the limit are refused.
#include <boost/asio/io_context.hpp>
#include <boost/beast/_experimental/test/stream.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

namespace beast = boost::beast;
namespace websocket = beast::websocket;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  constexpr std::size_t kMaxMessage = 64 * 1024;
  static boost::asio::io_context ioc;  // one per process: an epoll instance per input is slow
  beast::test::stream client(ioc);
  websocket::stream<beast::test::stream> ws(ioc);
  ws.next_layer().connect(client);
  const std::string upgrade =
      "GET / HTTP/1.1\r\nHost: 127.0.0.1:8765\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
      "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n"
      "Sec-WebSocket-Protocol: foxglove.websocket.v1\r\n\r\n";
  ws.next_layer().append(upgrade);
  ws.next_layer().append(beast::string_view(reinterpret_cast<const char*>(data), size));
  ws.next_layer().close_remote();  // end of input after the fuzzed bytes
  ws.read_message_max(kMaxMessage);
  beast::error_code ec;
  ws.accept(ec);
  if (ec) std::abort();  // the upgrade itself is valid
  beast::flat_buffer buffer;
  for (int i = 0; i < 1000; ++i) {
    buffer.clear();
    const std::size_t n = ws.read(buffer, ec);
    if (ec) break;
    if (n > kMaxMessage) std::abort();
  }
  return 0;
}
