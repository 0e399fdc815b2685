#include "server/unfinished_mbap_frame.hpp"

#include <algorithm>

#include "protocol/limits.hpp"
#include "protocol/mbap_framer.hpp"

namespace mblab::server {

void UnfinishedMbapFrame::add(std::size_t count, const std::optional<protocol::Adu>& frame,
                              Clock::time_point now) {
    if (bytes_ == 0) started_ = now;
    bytes_ += count;
    if (!frame) return;
    header_ = protocol::to_mbap_header(frame->header);
    if (!frame->pdu.empty()) function_ = frame->pdu.front();
}

void UnfinishedMbapFrame::begin_overlong(const protocol::MbapHeader& header,
                                         Clock::time_point started) {
    // CTP 9.1.3 sends length 0xFF with a 6-byte body: it waits for the body like any
    // unfinished frame, then is answered 03 and the stream carries on.
    clear();
    header_ = header;
    bytes_ = protocol::limits::kMbapHeader;
    started_ = started;
    overlong_ = true;
}

bool UnfinishedMbapFrame::skip(std::span<const std::uint8_t> bytes) {
    if (bytes.empty()) return true;
    if (!function_) function_ = bytes.front();
    skipped_ += bytes.size();
    const auto room = protocol::limits::kMaxPdu - body_.size();
    const auto kept = bytes.first(std::min(bytes.size(), room));
    body_.insert(body_.end(), kept.begin(), kept.end());
    return skipped_ <= protocol::limits::kMaxPdu;
}

std::optional<UnfinishedMbapFrame::Answerable> UnfinishedMbapFrame::answerable() const {
    if (!header_ || header_->protocol_id != protocol::kModbusProtocolId || !function_)
        return std::nullopt;
    return Answerable{*header_, *function_};
}

std::span<const std::uint8_t> UnfinishedMbapFrame::requests_after_body() const {
    if (body_.size() < 2) return {};
    // The body's first byte is the overlong frame's function code, never a request's start.
    const auto after_function = std::span(body_).subspan(1);
    return after_function.subspan(protocol::mbap_resync_offset(after_function));
}

void UnfinishedMbapFrame::clear() {
    bytes_ = 0;
    started_ = {};
    header_.reset();
    function_.reset();
    overlong_ = false;
    skipped_ = 0;
    if (body_.capacity() > 0) body_ = {};  // an overlong frame is rare: give its memory back
}

}  // namespace mblab::server
