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
    auto endpoint =
        target.secure ? transport::parse_mbaps_url(text) : transport::parse_tcp_url(text);
    if (!endpoint) return endpoint.error();
    target.name = transport::format_tcp_url(*endpoint, target.secure);
    target.tcp = Endpoint{endpoint->address().to_string(), endpoint->port(), nullptr};
    // The certificate names what the user typed: "localhost" is a DNS name, not 127.0.0.1.
    const auto host = text.substr(std::string_view("mbaps://").size());
    target.server_name =
        host.starts_with("localhost") ? std::string("localhost") : endpoint->address().to_string();
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
