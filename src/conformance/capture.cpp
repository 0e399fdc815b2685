#include "conformance/capture.hpp"

namespace mblab::conformance {

namespace {
CaptureEvent event(CaptureEvent::Kind kind) {
    return CaptureEvent{kind, std::chrono::system_clock::now(), {}, {}, false, {}};
}

std::size_t footprint(const CaptureEvent& e) {
    return sizeof(CaptureEvent) + e.bytes.size() + e.label.size();
}
}  // namespace

void Capture::keep(CaptureEvent e) {
    e.label = label_;
    kept_ += footprint(e);
    events_.push_back(std::move(e));
    if (bound_ == 0 || kept_ <= bound_) return;
    // Down to half the bound at once, so each event is moved a bounded number of times however
    // long the run; then on to the next connection's opening.
    std::size_t cut = 0;
    while (cut + 1 < events_.size() &&
           (kept_ > bound_ / 2 || events_[cut].kind != CaptureEvent::Kind::Open)) {
        kept_ -= footprint(events_[cut]);
        dropped_bytes_ += events_[cut].bytes.size();
        ++cut;
    }
    events_.erase(events_.begin(), events_.begin() + static_cast<std::ptrdiff_t>(cut));
}

void Capture::on_open(const client::LinkAddresses& addresses) {
    auto e = event(CaptureEvent::Kind::Open);
    e.addresses = addresses;
    keep(std::move(e));
}

void Capture::on_sent(std::span<const std::uint8_t> bytes) {
    auto e = event(CaptureEvent::Kind::Sent);
    e.bytes.assign(bytes.begin(), bytes.end());
    keep(std::move(e));
}

void Capture::on_received(std::span<const std::uint8_t> bytes) {
    auto e = event(CaptureEvent::Kind::Received);
    e.bytes.assign(bytes.begin(), bytes.end());
    keep(std::move(e));
}

void Capture::on_close(bool by_peer) {
    auto e = event(CaptureEvent::Kind::Close);
    e.by_peer = by_peer;
    keep(std::move(e));
}

}  // namespace mblab::conformance
