#include "client/tcp_link.hpp"

#include <utility>

namespace mblab::client {

protocol::Result<std::unique_ptr<Link>, LinkError> TcpLink::open(const Endpoint& endpoint,
                                                                 std::string name,
                                                                 std::chrono::milliseconds timeout) {
    auto raw = RawLink::connect(endpoint, timeout);
    if (!raw) return raw.error();
    return std::unique_ptr<Link>(new TcpLink(std::move(raw.value()), std::move(name)));
}

bool TcpLink::send(std::span<const std::uint8_t> adu, LinkError& error) {
    return raw_.send(adu, error);
}

Received TcpLink::receive_frame(std::chrono::milliseconds timeout) {
    return raw_.receive_frame(timeout);
}

}  // namespace mblab::client
