#include "client/tcp_link.hpp"

#include <utility>

namespace mblab::client {

protocol::Result<std::unique_ptr<Link>, LinkError> TcpLink::open(const Endpoint& endpoint,
                                                                 std::string name,
                                                                 std::chrono::milliseconds timeout,
                                                                 LinkObserver* observer) {
    auto raw = RawLink::connect(endpoint, timeout, observer);
    if (!raw) return raw.error();
    return std::unique_ptr<Link>(new TcpLink(std::move(raw.value()), std::move(name)));
}

bool TcpLink::send(std::span<const std::uint8_t> adu, LinkError& error) {
    return raw_.send(adu, error);
}

Received TcpLink::receive_frame(std::chrono::milliseconds timeout) {
    Received received = raw_.receive_frame(timeout);
    if (received.status == ReceiveStatus::Malformed && received.bytes.size() >= 6) {
        const unsigned length = (received.bytes[4] << 8) | received.bytes[5];
        received.detail =
            "MBAP length " + std::to_string(length) + " cannot describe a frame (must be 2..254)";
    }
    return received;
}

}  // namespace mblab::client
