#include "client/tcp_link.hpp"

#include <utility>

#include "client/tls_sniff.hpp"
#include "protocol/mbap_header.hpp"

namespace mblab::client {

protocol::Result<std::unique_ptr<Link>, LinkError> TcpLink::open(const Endpoint& endpoint,
                                                                 std::string name,
                                                                 std::chrono::milliseconds timeout,
                                                                 LinkObserver* observer) {
    auto raw = RawLink::connect(endpoint, timeout, observer);
    if (!raw) return raw.error();
    return std::unique_ptr<Link>(new TcpLink(std::move(raw.value()), std::move(name), endpoint));
}

bool TcpLink::send(std::span<const std::uint8_t> adu, LinkError& error) {
    return raw_.send(adu, error);
}

Received TcpLink::receive_frame(std::chrono::milliseconds timeout) {
    Received received = raw_.receive_frame(timeout);
    const bool first = !heard_;
    heard_ = heard_ || !received.bytes.empty();
    // Over plain TCP, a TLS server's first bytes, or its close before any byte, mean the port
    // wants mbaps://; once the connection has carried Modbus, neither means anything more.
    if (first && !endpoint_.tls) {
        if (looks_like_tls(received.bytes)) {
            received.status = ReceiveStatus::Malformed;
            received.detail = tls_answer_text(endpoint_, received.bytes);
            return received;
        }
        if (received.status == ReceiveStatus::Closed && received.bytes.empty()) {
            if (auto tls = sniff_tls(endpoint_, timeout)) received.detail = std::move(*tls);
            return received;
        }
    }
    // The link's lenient framer lets every header through but one whose length no frame has.
    const auto header = protocol::read_mbap_frame(received.bytes);
    if (received.status == ReceiveStatus::Malformed && header) {
        received.detail = "MBAP length " + std::to_string(header->header.length) +
                          " cannot describe a frame (must be 2..254)";
    }
    return received;
}

}  // namespace mblab::client
