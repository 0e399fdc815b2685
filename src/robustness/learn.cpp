#include "robustness/learn.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <deque>
#include <map>
#include <optional>
#include <set>
#include <tuple>

#include "conformance/pcap_format.hpp"
#include "protocol/framer.hpp"

namespace mblab::robustness {

namespace {

using Bytes = std::vector<std::uint8_t>;

struct Endpoint {
    std::array<std::uint8_t, 16> ip{};
    bool ipv6 = false;
    std::uint16_t port = 0;
    auto operator<=>(const Endpoint&) const = default;
};

// One direction of a connection: where its bytes start and the segments that carry them.
struct Direction {
    std::optional<std::uint32_t> first_seq;  // after the SYN, when it was captured
    std::vector<const TcpSegment*> data;
};

struct Flow {
    Direction requests;  // client to server
    Direction answers;
};

struct Frame {
    std::uint16_t transaction = 0;
    std::uint8_t unit = 0;
    Bytes pdu;
};

struct Exchange {
    std::uint8_t unit = 0;
    Bytes request;
    std::optional<Bytes> answer;
};

// The bytes of one direction in sequence order. Without the SYN the capture began mid-stream:
// the lowest sequence number starts it, and the bytes up to the first whole MBAP frame are cut.
Bytes reassemble(const Direction& direction) {
    if (direction.data.empty()) return {};
    std::uint32_t base = direction.first_seq.value_or(direction.data.front()->seq);
    if (!direction.first_seq) {
        for (const auto* segment : direction.data) {
            if (static_cast<std::int32_t>(segment->seq - base) < 0) base = segment->seq;
        }
    }
    std::vector<std::pair<std::uint32_t, const TcpSegment*>> ordered;
    for (const auto* segment : direction.data) {
        const std::uint32_t offset = segment->seq - base;
        // Before the start (a retransmitted SYN's data, say) or over 2 GiB in: not learned from.
        if (offset > 0x7FFFFFFFU) continue;
        ordered.emplace_back(offset, segment);
    }
    // Stable: of two copies at one offset, the one captured first wins.
    std::stable_sort(ordered.begin(), ordered.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    Bytes out;
    for (const auto& [offset, segment] : ordered) {
        const std::uint64_t end = std::uint64_t{offset} + segment->payload.size();
        if (end <= out.size()) continue;  // retransmitted
        if (offset > out.size()) break;   // a gap: what follows cannot be framed
        out.insert(out.end(), segment->payload.begin() + static_cast<long>(out.size() - offset),
                   segment->payload.end());
    }
    if (!direction.first_seq) {
        // Two whole ADUs and a bit show where frames start; scanning more costs without telling.
        constexpr std::size_t kResyncWindow = 600;
        const auto window = std::span(out).first(std::min(out.size(), kResyncWindow));
        const std::size_t start = protocol::mbap_resync_offset(window);
        out.erase(out.begin(), out.begin() + static_cast<long>(std::min(start, out.size())));
    }
    return out;
}

std::vector<Frame> frames_of(const Bytes& bytes) {
    std::vector<Frame> frames;
    protocol::Framer framer({.framing = protocol::Framing::Mbap});
    std::span<const std::uint8_t> rest(bytes);
    while (!rest.empty()) {
        std::size_t consumed = 0;
        const auto event = framer.feed(rest, consumed);
        rest = rest.subspan(consumed);
        if (event.is_frame()) {
            frames.push_back({event.header.transaction_id, event.header.unit,
                              Bytes(event.pdu.begin(), event.pdu.end())});
        } else if (event.is_error() && event.adu.empty()) {
            break;  // a length no frame has: where the next frame starts is unknown
        } else if (!event.is_error()) {
            break;
        }
    }
    return frames;
}

// Requests in order, each with the first answer of the same transaction id, unit and function
// not yet taken.
void pair(const Flow& flow, std::vector<Exchange>& out) {
    std::map<std::uint16_t, std::deque<Frame>> answers;
    for (auto& frame : frames_of(reassemble(flow.answers)))
        answers[frame.transaction].push_back(std::move(frame));
    for (auto& request : frames_of(reassemble(flow.requests))) {
        Exchange exchange{request.unit, std::move(request.pdu), std::nullopt};
        auto& waiting = answers[request.transaction];
        if (!waiting.empty()) {
            Frame answer = std::move(waiting.front());
            waiting.pop_front();
            if (answer.unit == exchange.unit && (answer.pdu[0] & 0x7F) == exchange.request[0])
                exchange.answer = std::move(answer.pdu);
        }
        out.push_back(std::move(exchange));
    }
}

std::vector<Exchange> exchanges(const PcapContents& capture, std::uint16_t port) {
    std::vector<Flow> flows;
    // The flow of each (client, server) pair now: a new SYN from the client starts another.
    std::map<std::pair<Endpoint, Endpoint>, std::size_t> current;
    for (const auto& segment : capture.segments) {
        const Endpoint src{segment.src_ip, segment.ipv6, segment.src_port};
        const Endpoint dst{segment.dst_ip, segment.ipv6, segment.dst_port};
        const bool to_server = segment.dst_port == port;
        if (!to_server && segment.src_port != port) continue;
        const auto key = to_server ? std::pair(src, dst) : std::pair(dst, src);
        const bool syn = (segment.flags & conformance::pcap::kTcpSyn) != 0;
        auto found = current.find(key);
        // A SYN with another initial sequence number is a new connection on the same ports; with
        // the same one, the SYN again.
        const bool reopened = found != current.end() && to_server && syn &&
                              flows[found->second].requests.first_seq != segment.seq + 1;
        if (found == current.end() || reopened) {
            flows.emplace_back();
            found = current.insert_or_assign(key, flows.size() - 1).first;
        }
        Direction& direction =
            to_server ? flows[found->second].requests : flows[found->second].answers;
        if (syn && !direction.first_seq) direction.first_seq = segment.seq + 1;
        if (!segment.payload.empty()) direction.data.push_back(&segment);
    }
    std::vector<Exchange> out;
    for (const auto& flow : flows)
        pair(flow, out);
    return out;
}

bool is_exception(const Exchange& e) {
    return e.answer && (*e.answer)[0] == (e.request[0] | 0x80);
}

// FC 03 answered with the registers asked for: the address and quantity.
std::optional<std::pair<std::uint16_t, std::uint16_t>> holding_read(const Exchange& e) {
    if (!e.answer || e.request[0] != 0x03 || e.request.size() != 5) return std::nullopt;
    AnsweredRanges scratch;
    if (!note_answered(e.request, *e.answer, scratch)) return std::nullopt;
    return std::pair(static_cast<std::uint16_t>(e.request[1] << 8 | e.request[2]),
                     static_cast<std::uint16_t>(e.request[3] << 8 | e.request[4]));
}

}  // namespace

protocol::Result<Recon, std::string> learn_recon(const PcapContents& capture, std::uint16_t port,
                                                 std::string_view name) {
    const auto all = exchanges(capture, port);
    const auto answered = static_cast<std::size_t>(
        std::count_if(all.begin(), all.end(), [](const Exchange& e) { return e.answer; }));
    // Units by answers, then by number: the first with an FC 03 read answered is the one checked.
    std::map<std::uint8_t, std::size_t> answers_of;
    std::set<std::uint8_t> readable;
    Recon recon;
    for (const auto& e : all) {
        if (!e.answer) continue;
        ++answers_of[e.unit];
        if (holding_read(e)) readable.insert(e.unit);
        recon.answers_unit_0 |= e.unit == 0;
        recon.answers_unit_255 |= e.unit == 0xFF;
    }
    std::optional<std::uint8_t> unit;
    for (const auto& [candidate, count] : answers_of) {
        if (readable.count(candidate) != 0 && (!unit || count > answers_of[*unit]))
            unit = candidate;
    }
    if (!unit) {
        return fmt::format(
            "{}: no FC 03 read answered in {} Modbus/TCP requests to port {}: nothing to check "
            "liveness with",
            name, all.size(), port);
    }
    recon.unit = *unit;
    recon.max_read = 0;
    recon.check_address = 0xFFFF;
    std::set<std::uint8_t> served;
    std::set<std::uint8_t> refused;
    for (const auto& e : all) {
        if (e.unit != recon.unit || !e.answer) continue;
        if (is_exception(e) && e.answer->size() >= 2 && (*e.answer)[1] == 0x01) {
            refused.insert(e.request[0]);
            continue;
        }
        served.insert(e.request[0]);
        note_answered(e.request, *e.answer, recon.ranges);
        if (const auto read = holding_read(e)) {
            recon.check_address = std::min(recon.check_address, read->first);
            recon.max_read = std::max(recon.max_read, read->second);
        }
    }
    recon.served.assign(served.begin(), served.end());
    for (auto function : refused) {
        if (served.count(function) == 0) recon.not_served.push_back(function);
    }
    recon.source =
        fmt::format("learned from {} ({} requests, {} answers)", name, all.size(), answered);
    return recon;
}

}  // namespace mblab::robustness
