#include "conformance/capture.hpp"

namespace mblab::conformance {

namespace {
CaptureEvent event(CaptureEvent::Kind kind) {
    return CaptureEvent{kind, std::chrono::system_clock::now(), {}, {}, false};
}
}  // namespace

void Capture::on_open(const client::LinkAddresses& addresses) {
    events_.push_back(event(CaptureEvent::Kind::Open));
    events_.back().addresses = addresses;
}

void Capture::on_sent(std::span<const std::uint8_t> bytes) {
    events_.push_back(event(CaptureEvent::Kind::Sent));
    events_.back().bytes.assign(bytes.begin(), bytes.end());
}

void Capture::on_received(std::span<const std::uint8_t> bytes) {
    events_.push_back(event(CaptureEvent::Kind::Received));
    events_.back().bytes.assign(bytes.begin(), bytes.end());
}

void Capture::on_close(bool by_peer) {
    events_.push_back(event(CaptureEvent::Kind::Close));
    events_.back().by_peer = by_peer;
}

}  // namespace mblab::conformance
