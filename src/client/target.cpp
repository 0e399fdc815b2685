#include "client/target.hpp"

#include <array>

#include "client/tcp_link.hpp"
#include "transport/tcp_url.hpp"

namespace mblab::client {

namespace {

constexpr std::array<std::string_view, 3> kSerialSchemes = {"rtu://", "ascii://", "rtu+tcp://"};

}  // namespace

protocol::Result<Target, std::string> parse_target(std::string_view text) {
    for (auto scheme : kSerialSchemes) {
        if (text.starts_with(scheme)) {
            return std::string(text) + ": " + std::string(scheme.substr(0, scheme.size() - 3)) +
                   " targets are not supported yet (use tcp://HOST[:PORT])";
        }
    }
    auto endpoint = transport::parse_tcp_url(text);
    if (!endpoint) return endpoint.error();
    Target target;
    target.name = transport::format_tcp_url(*endpoint);
    target.endpoint = {endpoint->address().to_string(), endpoint->port()};
    return target;
}

protocol::Result<std::unique_ptr<Link>, LinkError> open_link(const Target& target,
                                                            std::chrono::milliseconds timeout) {
    return TcpLink::open(target.endpoint, target.name, timeout);
}

}  // namespace mblab::client
