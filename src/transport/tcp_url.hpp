#pragma once

#include <asio/ip/tcp.hpp>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "protocol/result.hpp"

// "tcp://plc-01.plant.lan:1502" <-> a host and a port, and the host's addresses. Plants name
// their PLCs, so HOST is a DNS name, an IPv4 address or "[IPv6]"; a name is resolved the way the
// system resolves it (getaddrinfo: /etc/hosts, DNS), IPv4 and IPv6, in the system's order.
namespace mblab::transport {

inline constexpr std::uint16_t kModbusTcpPort = 502;
inline constexpr std::uint16_t kMbapsPort = 802;  // Modbus/TCP Security

// A TCP address as the user wrote it: `host` is a name or a numeric address, without brackets.
struct TcpAddress {
    std::string host;
    std::uint16_t port = kModbusTcpPort;
};

// Accepts "tcp://HOST[:PORT]" and "HOST[:PORT]"; PORT defaults to 502. Checks the form only:
// nothing is resolved. The error names what is wrong and shows the expected form.
protocol::Result<TcpAddress, std::string> parse_tcp_address(std::string_view url);

// Modbus/TCP Security: "mbaps://HOST[:PORT]", PORT defaulting to 802.
bool is_mbaps_url(std::string_view url);
protocol::Result<TcpAddress, std::string> parse_mbaps_address(std::string_view url);

// Every address of the host, in the order the system gives them (a numeric host is its own one
// address). The error is one line: "bad address 'URL': cannot resolve 'HOST': WHY".
protocol::Result<std::vector<asio::ip::tcp::endpoint>, std::string> resolve_tcp_address(
    std::string_view url, const TcpAddress& address);

// parse_tcp_address/parse_mbaps_address, then the first address the host resolves to: for a
// listener, which binds one address.
protocol::Result<asio::ip::tcp::endpoint, std::string> parse_tcp_url(std::string_view url);
protocol::Result<asio::ip::tcp::endpoint, std::string> parse_mbaps_url(std::string_view url);

// "127.0.0.1:1502" or "[::1]:1502".
std::string endpoint_text(const asio::ip::tcp::endpoint& endpoint);
// "tcp://127.0.0.1:1502", "tcp://[::1]:1502" or "tcp://plc-01.plant.lan:1502"; "mbaps://..."
// when `secure`.
std::string format_tcp_url(const asio::ip::tcp::endpoint& endpoint, bool secure = false);
std::string format_tcp_url(const TcpAddress& address, bool secure = false);

}  // namespace mblab::transport
