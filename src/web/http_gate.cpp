#include "web/http_gate.hpp"

#include <arpa/inet.h>
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <charconv>

#include "web/json_text.hpp"

namespace mblab::web {

namespace {

// The names a loopback address goes by on Debian (/etc/hosts) besides the literals.
constexpr std::array<std::string_view, 4> kLoopbackNames{"localhost", "localhost.localdomain",
                                                         "ip6-localhost", "ip6-loopback"};

std::string lower(std::string_view text) {
    std::string out(text);
    for (auto& c : out)
        if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
    return out;
}

enum class Literal { None, Loopback, Wildcard, Other };

Literal literal_kind(const std::string& host) {
    in_addr v4{};
    in6_addr v6{};
    if (::inet_pton(AF_INET, host.c_str(), &v4) == 1) {
        const auto address = ntohl(v4.s_addr);
        if ((address >> 24) == 127) return Literal::Loopback;
        return address == 0 ? Literal::Wildcard : Literal::Other;
    }
    if (::inet_pton(AF_INET6, host.c_str(), &v6) == 1) {
        if (IN6_IS_ADDR_LOOPBACK(&v6)) return Literal::Loopback;
        return IN6_IS_ADDR_UNSPECIFIED(&v6) ? Literal::Wildcard : Literal::Other;
    }
    return Literal::None;
}

HttpReply refusal(int status, const std::string& reason) {
    return {status, json_text({{"error", reason}})};
}

bool is_json(const std::string* content_type) {
    if (!content_type) return false;
    auto media = lower(content_type->substr(0, content_type->find(';')));
    while (!media.empty() && (media.back() == ' ' || media.back() == '\t'))
        media.pop_back();
    return media == "application/json";
}

}  // namespace

bool same_secret(std::string_view given, std::string_view expected) {
    unsigned difference = given.size() == expected.size() ? 0U : 1U;
    for (std::size_t i = 0; i < expected.size(); ++i) {
        const auto g = i < given.size() ? static_cast<unsigned char>(given[i]) : 0U;
        difference |= g ^ static_cast<unsigned char>(expected[i]);
    }
    return difference == 0;
}

HttpGate::HttpGate(GateOptions options) : options_(std::move(options)) {
    for (auto& name : options_.names)
        name = lower(name);
}

bool HttpGate::host_allowed(std::string_view text) const {
    std::string host;
    std::string_view port_text;
    if (!text.empty() && text.front() == '[') {
        const auto close = text.find(']');
        if (close == std::string_view::npos) return false;
        host = std::string(text.substr(1, close - 1));
        const auto rest = text.substr(close + 1);
        if (!rest.empty() && rest.front() != ':') return false;
        port_text = rest.empty() ? rest : rest.substr(1);
    } else {
        const auto colon = text.find(':');
        host = std::string(text.substr(0, colon));
        port_text = colon == std::string_view::npos ? std::string_view() : text.substr(colon + 1);
    }
    unsigned port = 80;
    if (!port_text.empty()) {
        auto [at, ec] =
            std::from_chars(port_text.data(), port_text.data() + port_text.size(), port);
        if (ec != std::errc() || at != port_text.data() + port_text.size()) return false;
    }
    if (port != options_.port) return false;
    host = lower(host);
    if (!host.empty() && host.back() == '.') host.pop_back();
    if (std::find(kLoopbackNames.begin(), kLoopbackNames.end(), host) != kLoopbackNames.end() ||
        std::find(options_.names.begin(), options_.names.end(), host) != options_.names.end()) {
        return true;
    }
    // An address literal cannot be rebound by DNS; a name other than those above can.
    switch (literal_kind(host)) {
        case Literal::Loopback:
            return true;
        case Literal::None:
        case Literal::Wildcard:
            return false;
        case Literal::Other:
            return literal_kind(options_.bound_host) == Literal::Wildcard ||
                   host == options_.bound_host;
    }
    return false;
}

bool HttpGate::origin_allowed(std::string_view origin) const {
    constexpr std::string_view scheme = "http://";
    if (origin.substr(0, scheme.size()) != scheme) return false;
    return host_allowed(origin.substr(scheme.size()));
}

std::optional<HttpReply> HttpGate::check(const HttpRequest& head) const {
    const auto* host = head.header("host");
    if (!host) return refusal(400, "a request needs a Host header");
    if (!options_.any_host && !host_allowed(*host)) {
        return refusal(403, fmt::format("Host '{}' is not this server's address (a page on another "
                                        "site may have been pointed here); serve "
                                        "--http-allow-host NAME takes a host name",
                                        *host));
    }
    const auto& method = head.method;
    if (method == "GET" || method == "HEAD") return std::nullopt;
    if (method != "POST" && method != "PUT" && method != "DELETE" && method != "PATCH") {
        return refusal(405, fmt::format("{} is not a method this server takes", method));
    }
    const auto* origin = head.header("origin");
    if (origin && !origin_allowed(*origin)) {
        return refusal(403, fmt::format("a change from origin '{}' is refused: only pages of this "
                                        "server may make one",
                                        *origin));
    }
    const auto* site = head.header("sec-fetch-site");
    if (site && *site != "same-origin" && *site != "none") {
        return refusal(403, fmt::format("a change from a {} page is refused", *site));
    }
    if (!options_.token.empty()) {
        const auto* authorization = head.header("authorization");
        if (!authorization || !same_secret(*authorization, "Bearer " + options_.token)) {
            return refusal(401,
                           "this server takes changes with \"Authorization: Bearer TOKEN\" "
                           "(the token serve printed, or --http-token)");
        }
    }
    const bool needs_json = method != "DELETE" || head.body_length > 0;
    if (needs_json && !is_json(head.header("content-type"))) {
        return refusal(415, fmt::format("{} takes a body of Content-Type: application/json "
                                        "(with curl: -H 'Content-Type: application/json')",
                                        method));
    }
    return std::nullopt;
}

}  // namespace mblab::web
