#include "cli/frame_log.hpp"

#include <fmt/core.h>

#include "cli/pdu_text.hpp"
#include "client/adu_codec.hpp"

namespace mblab::cli {

std::optional<DecodeDepth> parse_decode_depth(std::string_view name) {
    if (name == "app") return DecodeDepth::App;
    if (name == "frame") return DecodeDepth::Frame;
    if (name == "bytes") return DecodeDepth::Bytes;
    return std::nullopt;
}

void FrameLog::on_frame(client::FrameDirection direction, client::Framing framing,
                        std::span<const std::uint8_t> adu) {
    const bool sent = direction == client::FrameDirection::Sent;
    const char* mark = sent ? ">" : "<";
    if (depth_ == DecodeDepth::Bytes) fmt::print(out_, "{} {}\n", mark, hex_bytes(adu));
    auto parts = client::unwrap_frame(framing, adu);
    if (!parts) {
        fmt::print(out_, "{}   not a frame: {}\n", mark, parts.error());
        return;
    }
    if (depth_ != DecodeDepth::App) {
        if (const auto& mbap = parts->mbap) {
            fmt::print(
                out_,
                "{}   MBAP transaction id {} (0x{:04X}), protocol id {}, length {}, unit id {}\n",
                mark, mbap->transaction_id, mbap->transaction_id, mbap->protocol_id, mbap->length,
                mbap->unit_id);
        } else {
            fmt::print(out_, "{}   address {}\n", mark, parts->unit);
        }
    }
    fmt::print(out_, "{}   {}\n", mark,
               sent ? describe_request_pdu(parts->pdu) : describe_response_pdu(parts->pdu));
    std::fflush(out_);
}

void FrameLog::on_note(std::string_view note) {
    fmt::print(out_, "* {}\n", note);
    std::fflush(out_);
}

}  // namespace mblab::cli
