#include "client/target.hpp"

#include "client/stream_link.hpp"
#include "client/tcp_link.hpp"
#include "transport/tcp_url.hpp"

namespace mblab::client {

protocol::Result<Target, std::string> parse_target(std::string_view text) {
    Target target;
    if (transport::is_serial_url(text)) {
        auto serial = transport::parse_serial_url(text);
        if (!serial) return serial.error();
        target.name = transport::format_serial_url(*serial);
        target.serial = std::move(serial.value());
        return target;
    }
    auto endpoint = transport::parse_tcp_url(text);
    if (!endpoint) return endpoint.error();
    target.name = transport::format_tcp_url(*endpoint);
    target.tcp = Endpoint{endpoint->address().to_string(), endpoint->port()};
    return target;
}

Framing framing_of(const Target& target) {
    if (target.tcp) return Framing::Mbap;
    return target.serial->kind == transport::SerialUrl::Kind::Ascii ? Framing::Ascii : Framing::Rtu;
}

protocol::Result<std::unique_ptr<Link>, LinkError> open_link(const Target& target,
                                                             std::chrono::milliseconds timeout,
                                                             LinkObserver* observer) {
    if (target.tcp) return TcpLink::open(*target.tcp, target.name, timeout, observer);
    if (target.serial->kind == transport::SerialUrl::Kind::RtuOverTcp) {
        return StreamLink::open_rtu_over_tcp(target.serial->endpoint, target.name, timeout);
    }
    return StreamLink::open_serial(*target.serial, target.name);
}

}  // namespace mblab::client
