#include "transport/tcp_url.hpp"

#include <netdb.h>
#include <sys/socket.h>

#include <algorithm>
#include <charconv>
#include <cstring>
#include <memory>

#include "transport/bad_address.hpp"

namespace mblab::transport {

namespace {

constexpr std::string_view kScheme = "tcp://";
constexpr std::string_view kSecureScheme = "mbaps://";

struct Form {
    std::string_view expected;
    std::uint16_t default_port;
};
constexpr Form kTcp{"expected tcp://HOST:PORT, e.g. tcp://127.0.0.1:502", kModbusTcpPort};
constexpr Form kMbaps{"expected mbaps://HOST:PORT, e.g. mbaps://127.0.0.1:802", kMbapsPort};

// A DNS name (RFC 1123 labels; '_' taken, as some plants use it) or something for the numeric
// parser: anything else is a typo, caught here rather than as a resolver's "not known".
bool plausible_host(std::string_view host) {
    return host.size() <= 253 && std::all_of(host.begin(), host.end(), [](char c) {
               return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                      c == '-' || c == '.' || c == '_' || c == ':' || c == '%';
           });
}

// HOST[:PORT] after the scheme.
protocol::Result<TcpAddress, std::string> parse_host_port(std::string_view url,
                                                          std::string_view rest, const Form& form) {
    const auto url_error = [&](std::string_view why) {
        return bad_address(url, why, form.expected);
    };
    if (!rest.empty() && rest.back() == '/') rest.remove_suffix(1);

    std::string_view host;
    std::string_view port_text;
    if (rest.starts_with('[')) {
        auto close = rest.find(']');
        if (close == std::string_view::npos) return url_error("missing ']' after IPv6 address");
        host = rest.substr(1, close - 1);
        auto after = rest.substr(close + 1);
        if (!after.empty()) {
            if (after.front() != ':') return url_error("unexpected text after ']'");
            port_text = after.substr(1);
            if (port_text.empty()) return url_error("empty port");
        }
    } else {
        auto colon = rest.rfind(':');
        if (colon != std::string_view::npos && rest.find(':') != colon) {
            return url_error("IPv6 addresses go in brackets");
        }
        host = rest.substr(0, colon);
        if (colon != std::string_view::npos) {
            port_text = rest.substr(colon + 1);
            if (port_text.empty()) return url_error("empty port");
        }
    }
    if (host.empty()) return url_error("missing host");

    std::uint16_t port = form.default_port;
    if (!port_text.empty()) {
        unsigned value = 0;
        auto [end, ec] =
            std::from_chars(port_text.data(), port_text.data() + port_text.size(), value);
        if (ec != std::errc{} || end != port_text.data() + port_text.size() || value > 65535) {
            return url_error("port must be a number from 0 to 65535");
        }
        port = static_cast<std::uint16_t>(value);
    }

    if (!plausible_host(host)) return url_error("host must be a name or an IP address");
    return TcpAddress{std::string(host), port};
}

protocol::Result<asio::ip::tcp::endpoint, std::string> first_address(
    std::string_view url, protocol::Result<TcpAddress, std::string> parsed) {
    if (!parsed) return parsed.error();
    auto found = resolve_tcp_address(url, *parsed);
    if (!found) return found.error();
    return found->front();
}

}  // namespace

protocol::Result<std::vector<asio::ip::tcp::endpoint>, std::string> resolve_tcp_address(
    std::string_view url, const TcpAddress& address) {
    asio::error_code ec;
    const auto numeric = asio::ip::make_address(address.host, ec);
    if (!ec) return std::vector{asio::ip::tcp::endpoint(numeric, address.port)};

    addrinfo hints{};
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = SOCK_STREAM;
    addrinfo* found = nullptr;
    const std::string port = std::to_string(address.port);
    if (int rc = ::getaddrinfo(address.host.c_str(), port.c_str(), &hints, &found); rc != 0) {
        return bad_address(url, "cannot resolve '" + address.host + "': " + ::gai_strerror(rc),
                           "a name in /etc/hosts or DNS, or an IP address");
    }
    std::unique_ptr<addrinfo, decltype(&::freeaddrinfo)> owner(found, &::freeaddrinfo);
    std::vector<asio::ip::tcp::endpoint> out;
    for (const addrinfo* info = found; info != nullptr; info = info->ai_next) {
        asio::ip::tcp::endpoint endpoint;
        if (info->ai_addrlen > endpoint.capacity()) continue;
        std::memcpy(endpoint.data(), info->ai_addr, info->ai_addrlen);
        endpoint.resize(info->ai_addrlen);
        if (std::find(out.begin(), out.end(), endpoint) == out.end()) out.push_back(endpoint);
    }
    if (out.empty()) {
        return bad_address(url, "'" + address.host + "' has no IPv4 or IPv6 address",
                           "a name in /etc/hosts or DNS, or an IP address");
    }
    return out;
}

protocol::Result<TcpAddress, std::string> parse_tcp_address(std::string_view url) {
    std::string_view rest = url;
    if (rest.starts_with(kScheme)) {
        rest.remove_prefix(kScheme.size());
    } else if (rest.find("://") != std::string_view::npos) {
        return bad_address(url, "only tcp:// is served over TCP", kTcp.expected);
    }
    return parse_host_port(url, rest, kTcp);
}

bool is_mbaps_url(std::string_view url) {
    return url.starts_with(kSecureScheme);
}

protocol::Result<TcpAddress, std::string> parse_mbaps_address(std::string_view url) {
    if (!is_mbaps_url(url)) return bad_address(url, "not an mbaps:// address", kMbaps.expected);
    return parse_host_port(url, url.substr(kSecureScheme.size()), kMbaps);
}

protocol::Result<asio::ip::tcp::endpoint, std::string> parse_tcp_url(std::string_view url) {
    return first_address(url, parse_tcp_address(url));
}

protocol::Result<asio::ip::tcp::endpoint, std::string> parse_mbaps_url(std::string_view url) {
    return first_address(url, parse_mbaps_address(url));
}

std::string endpoint_text(const asio::ip::tcp::endpoint& endpoint) {
    const auto host = endpoint.address().to_string();
    return (endpoint.address().is_v6() ? '[' + host + ']' : host) + ':' +
           std::to_string(endpoint.port());
}

std::string format_tcp_url(const asio::ip::tcp::endpoint& endpoint, bool secure) {
    return std::string(secure ? kSecureScheme : kScheme) + endpoint_text(endpoint);
}

std::string format_tcp_url(const TcpAddress& address, bool secure) {
    std::string out(secure ? kSecureScheme : kScheme);
    const bool v6 = address.host.find(':') != std::string::npos;
    out += v6 ? '[' + address.host + ']' : address.host;
    out += ':' + std::to_string(address.port);
    return out;
}

}  // namespace mblab::transport
