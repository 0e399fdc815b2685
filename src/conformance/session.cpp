#include "conformance/session.hpp"

#include <thread>

namespace mblab::conformance {

Session::Session(client::Endpoint endpoint, Dut dut, EngineOptions options,
                 client::LinkObserver* observer, Progress* progress)
    : endpoint_(std::move(endpoint)),
      dut_(std::move(dut)),
      facts_(dut_),
      options_(options),
      observer_(observer),
      progress_(progress) {}

client::RawLink* Session::link(client::LinkError& error) {
    if (link_ && link_->is_open()) return &*link_;
    link_.reset();
    auto connected = client::RawLink::connect(endpoint_, options_.connect_timeout, observer_);
    if (!connected) {
        error = connected.error();
        return nullptr;
    }
    link_.emplace(std::move(connected.value()));
    return &*link_;
}

void Session::close() {
    link_.reset();
}

bool Session::send(std::span<const std::uint8_t> bytes, std::size_t count, client::LinkError& error,
                   std::span<const std::size_t> split, std::chrono::milliseconds delay) {
    client::RawLink* open = link(error);
    if (open == nullptr) return false;
    requests_ += count;
    std::size_t from = 0;
    for (std::size_t cut : split) {
        if (cut <= from || cut >= bytes.size()) continue;
        if (!open->send(bytes.subspan(from, cut - from), error)) return false;
        std::this_thread::sleep_for(delay);
        from = cut;
    }
    return open->send(bytes.subspan(from), error);
}

client::Received Session::receive_frame(std::chrono::milliseconds timeout) {
    if (!link_) return {client::ReceiveStatus::Closed, {}, "connection closed"};
    return link_->receive_frame(timeout);
}

client::Received Session::receive_any(std::chrono::milliseconds timeout) {
    if (!link_) return {client::ReceiveStatus::Closed, {}, "connection closed"};
    return link_->receive_any(timeout);
}

}  // namespace mblab::conformance
