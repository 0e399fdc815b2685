#include "robustness/flood.hpp"

#include <algorithm>
#include <span>

#include "protocol/limits.hpp"
#include "protocol/mbap_header.hpp"

namespace mblab::robustness {

namespace {

constexpr std::size_t kStreamChunk = 16 * 1024;

// Calls `visit` with the PDU of each whole MBAP frame at the start of `bytes`; returns how many.
template <class Visit>
std::size_t each_frame(std::span<const std::uint8_t> bytes, Visit&& visit) {
    std::size_t count = 0;
    while (const auto frame = protocol::read_mbap_frame(bytes)) {
        const std::size_t size = protocol::limits::kMbapHeader + frame->header.length - 1;
        if (frame->header.length < 2 || size > bytes.size()) break;
        visit(frame->pdu.first(frame->header.length - 1));
        bytes = bytes.subspan(size);
        ++count;
    }
    return count;
}

// The value of an FC 06 request or answer to `address`, or nothing.
std::optional<std::uint16_t> written(std::span<const std::uint8_t> pdu, std::uint16_t address) {
    if (pdu.size() != 5 || pdu[0] != 0x06 || (pdu[1] << 8 | pdu[2]) != address) return std::nullopt;
    return static_cast<std::uint16_t>(pdu[3] << 8 | pdu[4]);
}

}  // namespace

std::uint16_t stream(client::Link& link, const Step& step, const std::optional<WriteLedger>& ledger,
                     std::chrono::milliseconds timeout, const RunClock& clock) {
    std::uint16_t acknowledged = 0;
    std::size_t answers = 0;
    auto take_answers = [&](std::chrono::milliseconds wait) {
        std::size_t taken = 0;
        while (link.is_open()) {
            const auto answer = link.next_frame(taken == 0 ? wait : std::chrono::milliseconds(0));
            if (answer.status != client::ReceiveStatus::Frame) break;
            ++taken;
            if (!ledger) continue;
            if (const auto value = written(answer.pdu, ledger->address))
                acknowledged = std::max(acknowledged, *value);
        }
        answers += taken;
        return taken;
    };
    const std::span<const std::uint8_t> bytes(step.bytes);
    std::size_t sent = 0;
    // A device that reads slowly gets less of the flood, not a longer one.
    const auto give_up = clock.now() + 2 * timeout;
    auto last_progress = clock.now();
    while (sent < bytes.size() && link.is_open() && clock.now() < give_up &&
           clock.now() - last_progress < timeout) {
        client::LinkError error;
        const std::size_t n =
            link.send_for(bytes.subspan(sent, std::min(kStreamChunk, bytes.size() - sent)),
                          std::chrono::milliseconds(20), error);
        sent += n;
        if (take_answers(std::chrono::milliseconds(0)) > 0 || n > 0) last_progress = clock.now();
    }
    // The answers still on their way, until each request has one, the device falls quiet, or as
    // long again as the writing was allowed: a slow device's last acknowledgements may go
    // unread, which only weakens the ledger's check, never makes it wrong.
    const std::size_t requests = each_frame(bytes.first(sent), [](auto) {});
    const auto answers_by = clock.now() + 2 * timeout;
    while (link.is_open() && answers < requests && clock.now() < answers_by &&
           take_answers(timeout) > 0) {
    }
    return acknowledged;
}

std::uint16_t highest_write(const std::vector<Step>& steps, std::uint16_t address) {
    std::uint16_t highest = 0;
    for (const auto& step : steps) {
        each_frame(step.bytes, [&](std::span<const std::uint8_t> pdu) {
            if (const auto value = written(pdu, address)) highest = std::max(highest, *value);
        });
    }
    return highest;
}

}  // namespace mblab::robustness
