#include "transport/tcp_url.hpp"

#include <charconv>

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

// HOST[:PORT] after the scheme.
protocol::Result<asio::ip::tcp::endpoint, std::string> parse_host_port(std::string_view url,
                                                                       std::string_view rest,
                                                                       const Form& form) {
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

    asio::ip::address address;
    if (host == "localhost") {
        address = asio::ip::address_v4::loopback();
    } else {
        asio::error_code ec;
        address = asio::ip::make_address(std::string(host), ec);
        if (ec) return url_error("host must be a numeric IP address or localhost");
    }
    return asio::ip::tcp::endpoint(address, port);
}

}  // namespace

protocol::Result<asio::ip::tcp::endpoint, std::string> parse_tcp_url(std::string_view url) {
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

protocol::Result<asio::ip::tcp::endpoint, std::string> parse_mbaps_url(std::string_view url) {
    if (!is_mbaps_url(url)) return bad_address(url, "not an mbaps:// address", kMbaps.expected);
    return parse_host_port(url, url.substr(kSecureScheme.size()), kMbaps);
}

std::string format_tcp_url(const asio::ip::tcp::endpoint& endpoint, bool secure) {
    std::string out(secure ? kSecureScheme : kScheme);
    if (endpoint.address().is_v6()) {
        out += '[' + endpoint.address().to_string() + ']';
    } else {
        out += endpoint.address().to_string();
    }
    out += ':' + std::to_string(endpoint.port());
    return out;
}

}  // namespace mblab::transport
