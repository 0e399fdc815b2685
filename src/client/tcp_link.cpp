#include "client/tcp_link.hpp"

#include <utility>

#include "protocol/mbap_header.hpp"

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
    // The link's lenient framer lets every header through but one whose length no frame has.
    const auto header = protocol::read_mbap_frame(received.bytes);
    if (received.status == ReceiveStatus::Malformed && header) {
        received.detail = "MBAP length " + std::to_string(header->header.length) +
                          " cannot describe a frame (must be 2..254)";
    }
    return received;
}

}  // namespace mblab::client
