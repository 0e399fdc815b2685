#include "robustness/storm_ladder.hpp"

#include <fmt/core.h>

#include <memory>
#include <thread>

#include "robustness/fuzz_case.hpp"
#include "robustness/storm_requests.hpp"
#include "support/comma_list.hpp"

namespace mblab::robustness {

namespace {

using Bytes = std::vector<std::uint8_t>;

// The answers waiting on the stream's connection, each counted; the link dropped when closed.
void take_answers(std::unique_ptr<client::Link>& link, StormCore& core) {
    while (link && link->is_open()) {
        const auto answer = link->next_frame(std::chrono::milliseconds(0));
        if (answer.status == client::ReceiveStatus::Frame) {
            core.answered(1);
            continue;
        }
        if (answer.status == client::ReceiveStatus::Closed) {
            link.reset();
            core.stream_lost();
        }
        break;
    }
}

}  // namespace

LadderRung storm(const StormTarget& target, StormKind kind, double rate,
                 std::chrono::milliseconds duration, std::span<const std::uint8_t> request) {
    StormCore core(kind, rate, Clock::now(), duration);
    const Bytes small = request.empty() ? storm_request(StormKind::Fc03, target.address)
                                        : Bytes(request.begin(), request.end());
    // The slow readers' requests, a block written over and over from where the last write ended.
    Bytes large;
    std::uint16_t transaction = 0;
    for (std::size_t i = 0; i < kSlowReaderBlock; ++i) {
        const auto frame = mbap_frame(++transaction, target.unit,
                                      protocol::encoded_pdu(protocol::ReadRegistersRequest{
                                          protocol::FunctionCode::ReadHoldingRegisters,
                                          target.large_address, target.large_quantity}));
        large.insert(large.end(), frame.begin(), frame.end());
    }
    const std::size_t large_frame = large.size() / kSlowReaderBlock;
    std::unique_ptr<client::Link> stream;
    struct Unread {
        std::unique_ptr<client::Link> link;
        std::size_t at = 0;  // into `large`
        std::size_t written = 0;
    };
    std::vector<Unread> unread;  // the slow readers, held until the rung ends
    std::size_t unread_bytes = 0;
    const auto open = [&]() -> std::unique_ptr<client::Link> {
        auto opened = target.dial();
        core.opened(static_cast<bool>(opened));
        return opened ? std::move(opened.value()) : nullptr;
    };
    while (!core.over(Clock::now())) {
        client::LinkError error;
        for (const auto& action : core.poll(Clock::now())) {
            for (std::size_t i = 0; i < action.count && !core.over(Clock::now()); ++i) {
                switch (action.what) {
                    case StormAction::Do::OpenStream:
                        stream = open();
                        break;
                    case StormAction::Do::SendRequests:
                        if (!stream) break;
                        if (!stream->send(mbap_frame(++transaction, target.unit, small), error)) {
                            stream.reset();
                            core.stream_lost();
                            break;
                        }
                        core.sent(1);
                        break;
                    case StormAction::Do::OpenAndClose:
                        if (auto link = open()) link->close();
                        break;
                    case StormAction::Do::OpenSlowReader:
                        if (auto link = open()) unread.push_back({std::move(link), 0});
                        break;
                    case StormAction::Do::OpenHalfOpen:
                        if (auto link = open()) {
                            // Three bytes of a request: the device waits for the rest.
                            const Bytes part = mbap_frame(++transaction, target.unit, small);
                            link->send(std::span(part).first(3), error);
                            if (!link->vanish()) link->close();
                        }
                        break;
                }
            }
        }
        // Each slow reader writes what the device takes without waiting, and reads nothing.
        const std::size_t frames_before = unread_bytes / large_frame;
        for (auto& reader : unread) {
            // Over TLS the channel takes what it is given and holds what the device has not
            // taken: the bound keeps the tester's memory bounded.
            if (!reader.link->is_open() || reader.written >= kSlowReaderMost) continue;
            const auto n = reader.link->send_for(std::span(large).subspan(reader.at),
                                                 std::chrono::milliseconds(0), error);
            reader.at = (reader.at + n) % large.size();
            reader.written += n;
            unread_bytes += n;
        }
        core.sent(unread_bytes / large_frame - frames_before);
        take_answers(stream, core);
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    for (auto& reader : unread)
        reader.link->close();
    return core.finish(Clock::now());
}

namespace {

// `text`'s rates; the message names `whole`, the option's text.
protocol::Result<std::vector<double>, std::string> rates_of(const std::string& text,
                                                            const std::string& whole) {
    std::vector<double> rates;
    for (const auto& item : comma_items(text)) {
        double rate = 0;
        try {
            std::size_t used = 0;
            rate = std::stod(item, &used);
            if (used != item.size()) rate = 0;
        } catch (const std::exception&) {
            rate = 0;
        }
        if (rate <= 0 || (!rates.empty() && rate <= rates.back()))
            return fmt::format("--ladder '{}': give rising rates per second, e.g. 100,500,1000",
                               whole);
        rates.push_back(rate);
    }
    if (rates.empty()) return fmt::format("--ladder '{}': no rate", whole);
    return rates;
}

}  // namespace

protocol::Result<std::vector<double>, std::string> parse_rates(const std::string& text) {
    return rates_of(text, text);
}

protocol::Result<std::vector<Ladder>, std::string> parse_ladders(const std::string& text) {
    const std::string group = std::string(kRequestsGroup) + ":";
    if (text.rfind(group, 0) != 0) {
        auto one = parse_ladder(text);
        if (!one) return one.error();
        return std::vector<Ladder>{std::move(*one)};
    }
    auto rates = rates_of(text.substr(group.size()), text);
    if (!rates) return rates.error();
    std::vector<Ladder> out;
    for (const auto kind : request_storms())
        out.push_back({kind, *rates});
    return out;
}

protocol::Result<std::vector<Ladder>, std::string> parse_ladders(
    std::span<const std::string> texts) {
    std::vector<Ladder> out;
    for (const auto& text : texts) {
        auto parsed = parse_ladders(text);
        if (!parsed) return parsed.error();
        for (auto& ladder : *parsed) {
            for (const auto& earlier : out) {
                if (earlier.kind == ladder.kind) {
                    return fmt::format(
                        "--ladder '{}': the {} storm is already on the ladder; give each storm "
                        "once",
                        text, storm_key(ladder.kind));
                }
            }
            out.push_back(std::move(ladder));
        }
    }
    return out;
}

protocol::Result<Ladder, std::string> parse_ladder(const std::string& text) {
    Ladder ladder;
    std::string rates = text;
    if (const auto colon = text.find(':'); colon != std::string::npos) {
        const auto key = text.substr(0, colon);
        bool known = false;
        for (const auto& storm : all_storms()) {
            if (key == storm.key) {
                ladder.kind = storm.kind;
                known = true;
            }
        }
        if (!known) {
            // The connection storms, then the request storms in the order of their codes.
            std::string names;
            for (const auto& storm : all_storms()) {
                if (!is_request_storm(storm.kind)) names += std::string(storm.key) + ", ";
            }
            for (const auto kind : request_storms())
                names += std::string(storm_key(kind)) + ", ";
            return fmt::format("--ladder '{}': '{}' is no storm ({}or {}: every request storm)",
                               text, key, names, kRequestsGroup);
        }
        rates = text.substr(colon + 1);
    }
    auto parsed = rates_of(rates, text);
    if (!parsed) return parsed.error();
    ladder.rates = std::move(*parsed);
    return ladder;
}

}  // namespace mblab::robustness
