#include "cli/frame_log.hpp"

#include <fmt/core.h>

#include "cli/pdu_text.hpp"
#include "client/hex_text.hpp"
#include "protocol/framer.hpp"

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
    if (depth_ == DecodeDepth::Bytes) fmt::print(out_, "{} {}\n", mark, client::hex_bytes(adu));
    protocol::Framer framer({framing});
    const auto frame = framer.whole_frame(adu);
    if (!frame) {
        fmt::print(out_, "{}   not a frame: {}\n", mark, frame.error());
        return;
    }
    const auto& header = frame->header;
    if (depth_ != DecodeDepth::App) {
        if (header.has_transaction()) {
            fmt::print(
                out_,
                "{}   MBAP transaction id {} (0x{:04X}), protocol id {}, length {}, unit id {}\n",
                mark, header.transaction_id, header.transaction_id, header.protocol_id,
                header.length, header.unit);
        } else {
            fmt::print(out_, "{}   address {}\n", mark, header.unit);
        }
    }
    fmt::print(out_, "{}   {}\n", mark,
               sent ? describe_request_pdu(frame->pdu) : describe_response_pdu(frame->pdu));
    std::fflush(out_);
}

void FrameLog::on_note(std::string_view note) {
    fmt::print(out_, "* {}\n", note);
    std::fflush(out_);
}

}  // namespace mblab::cli
