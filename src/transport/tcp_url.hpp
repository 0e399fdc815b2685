#pragma once

#include <asio/ip/tcp.hpp>
#include <cstdint>
#include <string>
#include <string_view>

#include "protocol/result.hpp"

// "tcp://127.0.0.1:1502" <-> an endpoint. Only numeric addresses and "localhost": a lab tool
// should not wait on DNS, and a name that resolves to several addresses makes "which one did we
// test" ambiguous.
namespace mblab::transport {

inline constexpr std::uint16_t kModbusTcpPort = 502;
inline constexpr std::uint16_t kMbapsPort = 802;  // Modbus/TCP Security

// Accepts "tcp://HOST[:PORT]" and "HOST[:PORT]"; HOST is an IPv4 address, "[IPv6]" or
// "localhost"; PORT defaults to 502. The error names what is wrong and shows the expected form.
protocol::Result<asio::ip::tcp::endpoint, std::string> parse_tcp_url(std::string_view url);

// Modbus/TCP Security: "mbaps://HOST[:PORT]", PORT defaulting to 802.
bool is_mbaps_url(std::string_view url);
protocol::Result<asio::ip::tcp::endpoint, std::string> parse_mbaps_url(std::string_view url);

// "tcp://127.0.0.1:1502" or "tcp://[::1]:1502"; "mbaps://..." when `secure`.
std::string format_tcp_url(const asio::ip::tcp::endpoint& endpoint, bool secure = false);

}  // namespace mblab::transport
