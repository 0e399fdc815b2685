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
    target.secure = transport::is_mbaps_url(text);
    auto address =
        target.secure ? transport::parse_mbaps_address(text) : transport::parse_tcp_address(text);
    if (!address) return address.error();
    // A name that does not resolve is the user's typo, said now; the link resolves it again when
    // it connects and tries every address in turn.
    if (auto found = transport::resolve_tcp_address(text, *address); !found) return found.error();
    target.name = transport::format_tcp_url(*address, target.secure);
    target.tcp = Endpoint{address->host, address->port, nullptr};
    // The certificate must name what the user typed: a DNS name or an IP address.
    target.server_name = address->host;
    return target;
}

std::string attach_tls(Target& target, const security::TlsFiles& files,
                       const security::ClientSettings& settings) {
    if (!target.secure) {
        if (!files.empty()) return "--cert, --key and --ca are for mbaps:// targets only";
        return {};
    }
    if (settings.verify_server) {
        if (auto missing = security::incomplete_files(files); !missing.empty()) {
            return missing + " for " + target.name;
        }
    }
    auto context = security::make_client_context(files, settings);
    if (!context) return context.error();
    target.tcp->tls = std::make_shared<const TlsSetup>(
        TlsSetup{std::move(context.value()), settings.verify_server ? target.server_name : ""});
    return {};
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
        return StreamLink::open_rtu_over_tcp(target.serial->endpoint, target.name, timeout,
                                             observer);
    }
    return StreamLink::open_serial(*target.serial, target.name, observer);
}

}  // namespace mblab::client
