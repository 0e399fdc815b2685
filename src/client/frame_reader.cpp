#include "client/frame_reader.hpp"

#include <utility>

namespace mblab::client {

void FrameReader::add(std::span<const std::uint8_t> bytes) {
    pending_.insert(pending_.end(), bytes.begin(), bytes.end());
}

void FrameReader::reset() {
    framer_.reset();
    pending_.clear();
    partial_.clear();
}

Received FrameReader::take(ReceiveStatus status, std::string detail) {
    Received out{status, std::move(partial_), std::move(detail)};
    out.bytes.insert(out.bytes.end(), pending_.begin(), pending_.end());
    partial_.clear();
    pending_.clear();
    framer_.reset();
    return out;
}

std::optional<Received> FrameReader::cut(const protocol::FrameEvent& event, std::size_t consumed) {
    if (event.is_frame()) {
        partial_.clear();
        Received out{ReceiveStatus::Frame, {event.adu.begin(), event.adu.end()}, {}};
        out.header = event.header;
        out.pdu.assign(event.pdu.begin(), event.pdu.end());
        out.violation = event.violation;
        return out;
    }
    if (!event.is_error()) return std::nullopt;
    if (!event.adu.empty()) {
        partial_.assign(event.adu.begin(), event.adu.end());
    } else if (framer_.framing() == protocol::Framing::Mbap) {
        // A header whose length describes no frame: where the next frame starts is unknown, so
        // nothing after it can be trusted either. It is all handed over.
        partial_.insert(partial_.end(), pending_.begin() + static_cast<long>(consumed),
                        pending_.end());
        pending_.clear();
    }
    Received out{ReceiveStatus::Malformed, std::move(partial_), event.error};
    partial_.clear();
    return out;
}

std::optional<Received> FrameReader::next() {
    while (!pending_.empty()) {
        std::size_t consumed = 0;
        const auto event = framer_.feed(pending_, consumed);
        partial_.insert(partial_.end(), pending_.begin(),
                        pending_.begin() + static_cast<long>(consumed));
        // The event may view `pending_`: it is copied out before those bytes go.
        auto done = cut(event, consumed);
        pending_.erase(pending_.begin(),
                       pending_.begin() + static_cast<long>(std::min(consumed, pending_.size())));
        if (done) return done;
    }
    return std::nullopt;
}

std::optional<Received> FrameReader::on_silence() {
    return cut(framer_.on_silence(), 0);
}

}  // namespace mblab::client
