#include "conformance/client_examiner.hpp"

#include <algorithm>
#include <utility>

#include "protocol/adu.hpp"
#include "protocol/adu_writer.hpp"
#include "protocol/function_code.hpp"
#include "protocol/limits.hpp"

namespace mblab::conformance {

namespace {

using namespace std::chrono_literals;

// The right answer follows a decoy by this much, so the two come in segments of their own.
constexpr auto kFollowUp = 50ms;
// LateReply: when the client has not asked again, the stale answer comes this long after its
// timeout ran out.
constexpr auto kLateMargin = 300ms;
constexpr auto kSegmentGap = 30ms;  // SplitAnswer
// Pipelined: how long the examiner waits for a second request before it answers what it has.
constexpr auto kPipelineWait = 200ms;
// Added to a transaction id for an answer nobody asked for: far from the ids a client uses next.
constexpr std::uint16_t kForeignTransaction = 0x5A5A;

constexpr std::uint8_t kReadHolding = 0x03;
constexpr std::uint8_t kReadInput = 0x04;

std::uint16_t word(std::span<const std::uint8_t> bytes, std::size_t at) {
    return static_cast<std::uint16_t>(bytes[at] << 8 | bytes[at + 1]);
}

void put_word(std::vector<std::uint8_t>& out, std::uint16_t value) {
    out.push_back(static_cast<std::uint8_t>(value >> 8));
    out.push_back(static_cast<std::uint8_t>(value & 0xFF));
}

bool is_register_read(std::uint8_t function) {
    return function == kReadHolding || function == kReadInput;
}

// The values of the registers `request` asks for: seeded, or the decoys.
std::vector<std::uint8_t> register_pdu(const ClientExaminer::Request& request, bool decoy,
                                       std::uint8_t function) {
    std::vector<std::uint8_t> pdu{function, static_cast<std::uint8_t>(request.count * 2)};
    for (std::uint32_t i = 0; i < request.count; ++i) {
        const std::uint32_t address = request.address + i;
        put_word(pdu, decoy ? decoy_value(address) : seeded_value(address));
    }
    return pdu;
}

}  // namespace

ClientExaminer::ClientExaminer(ClientCase scenario, ClientDeclarations declared,
                               Clock::time_point now, protocol::Framing framing)
    : scenario_(std::move(scenario)),
      declared_(std::move(declared)),
      started_(now),
      framing_(framing) {}

std::size_t ClientExaminer::opened(Clock::time_point now) {
    connections_.push_back(std::make_unique<Connection>(framing_));
    connections_.back()->opened_at = now;
    return connections_.size() - 1;
}

std::vector<ClientExaminer::Clock::time_point> ClientExaminer::connection_times() const {
    std::vector<Clock::time_point> times;
    for (const auto& connection : connections_)
        times.push_back(connection->opened_at);
    return times;
}

void ClientExaminer::received(std::size_t connection, std::span<const std::uint8_t> bytes,
                              Clock::time_point now) {
    if (connection >= connections_.size()) return;
    auto& framer = connections_[connection]->framer;
    while (!bytes.empty()) {
        std::size_t consumed = 0;
        const auto event = framer.feed(bytes, consumed);
        bytes = bytes.subspan(consumed);
        if (event.is_frame()) on_frame(connection, event, now);
    }
}

void ClientExaminer::quiet(std::size_t connection, Clock::time_point now) {
    if (connection >= connections_.size()) return;
    const auto event = connections_[connection]->framer.on_silence();
    if (event.is_frame()) on_frame(connection, event, now);
}

void ClientExaminer::on_frame(std::size_t connection, const protocol::FrameEvent& event,
                              Clock::time_point now) {
    Request request{now,
                    connection,
                    {event.adu.begin(), event.adu.end()},
                    event.header.transaction_id,
                    event.header.unit};
    if (!event.pdu.empty()) request.function = event.pdu.front();
    if (is_register_read(request.function) && event.pdu.size() >= 5) {
        request.address = word(event.pdu, 1);
        request.count = word(event.pdu, 3);
    }
    requests_.push_back(request);
    on_request(request, now);
}

std::vector<std::uint8_t> ClientExaminer::frame(std::uint16_t transaction_id, std::uint8_t unit,
                                                std::span<const std::uint8_t> pdu) const {
    std::vector<std::uint8_t> adu(protocol::limits::kMaxAsciiChars);
    protocol::AduHeader header;
    header.framing = framing_;
    header.unit = unit;
    header.transaction_id = transaction_id;
    adu.resize(protocol::write_adu(header, pdu, adu));
    return adu;
}

void ClientExaminer::closed(std::size_t connection, Clock::time_point) {
    if (connection >= connections_.size()) return;
    connections_[connection]->open = false;
    std::erase_if(pending_, [&](const Action& action) { return action.connection == connection; });
}

ClientExaminer::Clock::time_point ClientExaminer::deadline() const {
    auto next = pending_.empty() ? Clock::time_point::max() : pending_.front().at;
    if (pending_stale_) next = std::min(next, stale_.at);
    return std::min(next, pipeline_at_);
}

std::vector<ClientExaminer::Action> ClientExaminer::due(Clock::time_point now) {
    if (pending_stale_ && stale_.at <= now) {
        // The client did not ask again on time: the stale answer comes anyway, unmet.
        pending_stale_ = false;
        if (connections_[stale_.connection]->open) {
            answers_.push_back({now, stale_.connection, stale_.bytes, true});
            schedule(std::move(stale_));
        }
    }
    if (pipeline_at_ <= now) {
        pipeline_at_ = Clock::time_point::max();
        for (std::size_t c = 0; c < connections_.size(); ++c)
            answer_pipeline(c, now);
    }
    std::vector<Action> ready;
    auto split = std::find_if(pending_.begin(), pending_.end(),
                              [&](const Action& action) { return action.at > now; });
    ready.assign(std::make_move_iterator(pending_.begin()), std::make_move_iterator(split));
    pending_.erase(pending_.begin(), split);
    return ready;
}

void ClientExaminer::refused(std::size_t connection, std::string reason) {
    if (connection < connections_.size()) connections_[connection]->open = false;
    refusals_.push_back(std::move(reason));
}

std::vector<std::uint8_t> ClientExaminer::register_answer(const Request& request,
                                                          std::uint16_t transaction_id,
                                                          std::uint8_t unit, bool decoy) const {
    return frame(transaction_id, unit, register_pdu(request, decoy, request.function));
}

std::vector<std::uint8_t> ClientExaminer::right(const Request& request) const {
    if (!is_register_read(request.function) || request.count == 0 ||
        request.count > protocol::limits::kMaxReadRegisters) {
        // APP 7: a function the examiner does not serve is 01, a bad quantity 03.
        const std::uint8_t code = is_register_read(request.function) ? 0x03 : 0x01;
        const std::uint8_t pdu[] = {static_cast<std::uint8_t>(request.function | 0x80), code};
        return frame(request.transaction_id, request.unit, pdu);
    }
    return register_answer(request, request.transaction_id, request.unit, false);
}

void ClientExaminer::answer(const Request& request, std::vector<std::uint8_t> bytes, bool decoy,
                            Clock::time_point at) {
    if (!connections_[request.connection]->open) return;
    answers_.push_back({at, request.connection, bytes, decoy});
    schedule({Action::Kind::Send, request.connection, std::move(bytes), at});
}

void ClientExaminer::schedule(Action action) {
    const auto at = action.at;
    auto place = std::upper_bound(
        pending_.begin(), pending_.end(), at,
        [](Clock::time_point when, const Action& other) { return when < other.at; });
    pending_.insert(place, std::move(action));
}

void ClientExaminer::on_request(const Request& request, Clock::time_point now) {
    // SER 2.2: a broadcast is executed by every slave and answered by none.
    if (request.unit == 0 && framing_ != protocol::Framing::Mbap) return;
    if (request.unit != declared_.unit) return;  // not the unit the client was told: silence
    const std::size_t index = asked_++;
    const bool first = index == 0;
    const auto foreign_unit =
        static_cast<std::uint8_t>(declared_.unit == 0xFF ? 0xFE : declared_.unit + 1);
    switch (scenario_.scenario) {
        case ClientScenario::NoReply:
        case ClientScenario::Broadcast:
            return;
        case ClientScenario::Untrusted:
            // A client that took the certificate shows what it was told by whom it must not trust.
            answer(request, register_answer(request, request.transaction_id, request.unit, true),
                   true, now);
            return;
        case ClientScenario::LateReply:
            if (first) {
                if (declared_.timeout) {
                    stale_ = {Action::Kind::Send, request.connection,
                              register_answer(request, request.transaction_id, request.unit, true),
                              now + *declared_.timeout + kLateMargin};
                    pending_stale_ = true;
                }
                return;
            }
            if (pending_stale_) {
                pending_stale_ = false;
                const auto& asked_first = stale_;
                const bool reused = word(asked_first.bytes, 0) == request.transaction_id;
                if (!reused && asked_first.connection == request.connection) {
                    stale_met_wait_ = true;
                    answer(request, std::move(stale_.bytes), true, now);
                }
            }
            answer(request, right(request), false, now + kFollowUp);
            return;
        case ClientScenario::WrongTransaction:
            answer(request,
                   register_answer(
                       request,
                       static_cast<std::uint16_t>(request.transaction_id + kForeignTransaction),
                       request.unit, true),
                   true, now);
            answer(request, right(request), false, now + kFollowUp);
            return;
        case ClientScenario::WrongUnit:
            answer(request, register_answer(request, request.transaction_id, foreign_unit, true),
                   true, now);
            answer(request, right(request), false, now + kFollowUp);
            return;
        case ClientScenario::WrongFunction:
        case ClientScenario::Truncated:
        case ClientScenario::ExtraBytes:
        case ClientScenario::ByteCount:
        case ClientScenario::BadCheck:
            if (first && is_register_read(request.function)) {
                answer(request, malformed(request), true, now);
            } else {
                answer(request, right(request), false, now);
            }
            return;
        case ClientScenario::Exception: {
            const std::uint8_t pdu[] = {static_cast<std::uint8_t>(request.function | 0x80),
                                        scenario_.exception};
            answer(request, frame(request.transaction_id, request.unit, pdu), false, now);
            return;
        }
        case ClientScenario::SplitAnswer: {
            const auto whole = right(request);
            answers_.push_back({now, request.connection, whole, false});
            // Cut inside the MBAP header and inside the PDU: a reader must use the length field.
            const std::size_t cuts[] = {0, 3, std::min<std::size_t>(9, whole.size()), whole.size()};
            for (std::size_t i = 0; i + 1 < std::size(cuts); ++i) {
                schedule({Action::Kind::Send,
                          request.connection,
                          {whole.begin() + static_cast<std::ptrdiff_t>(cuts[i]),
                           whole.begin() + static_cast<std::ptrdiff_t>(cuts[i + 1])},
                          now + kSegmentGap * static_cast<int>(i)});
            }
            return;
        }
        case ClientScenario::TwoAnswers: {
            auto both = right(request);
            const auto unasked = register_answer(
                request, static_cast<std::uint16_t>(request.transaction_id + kForeignTransaction),
                request.unit, true);
            answers_.push_back({now, request.connection, unasked, true});
            both.insert(both.end(), unasked.begin(), unasked.end());
            answer(request, std::move(both), false, now);
            return;
        }
        case ClientScenario::CloseFin:
        case ClientScenario::CloseReset:
            if (first) {
                schedule({scenario_.scenario == ClientScenario::CloseFin ? Action::Kind::Close
                                                                         : Action::Kind::Reset,
                          request.connection,
                          {},
                          now});
                connections_[request.connection]->open = false;
            } else {
                answer(request, right(request), false, now);
            }
            return;
        case ClientScenario::Pipelined: {
            auto& waiting = connections_[request.connection]->outstanding;
            waiting.push_back(requests_.size() - 1);
            if (waiting.size() >= 2) {
                answer_pipeline(request.connection, now);
            } else {
                pipeline_at_ = std::min(pipeline_at_, now + kPipelineWait);
            }
            return;
        }
    }
}

std::vector<std::uint8_t> ClientExaminer::malformed(const Request& request) const {
    auto pdu = register_pdu(request, true, request.function);
    switch (scenario_.scenario) {
        case ClientScenario::WrongFunction:
            pdu[0] = request.function == kReadHolding ? kReadInput : kReadHolding;
            break;
        case ClientScenario::Truncated:
            pdu.pop_back();  // the byte count promises one byte more than comes
            break;
        case ClientScenario::ExtraBytes:
            pdu.push_back(0xDE);
            pdu.push_back(0xAD);
            break;
        case ClientScenario::BadCheck: {
            // SER 2.5.1.2, 2.5.2.2: the last check character is off by one, the frame else whole.
            auto bad = frame(request.transaction_id, request.unit, pdu);
            if (framing_ == protocol::Framing::Ascii) {
                auto& digit = bad[bad.size() - 3];  // the LRC's low hex digit, before CR LF
                digit = digit == '0' ? '1' : '0';
            } else {
                bad.back() ^= 1;
            }
            return bad;
        }
        default:
            // ByteCount: a consistent answer for one register fewer (one more when one was asked).
            if (request.count > 1) {
                pdu.resize(pdu.size() - 2);
            } else {
                put_word(pdu, decoy_value(request.address + 1U));
            }
            pdu[1] = static_cast<std::uint8_t>(pdu.size() - 2);
            break;
    }
    return frame(request.transaction_id, request.unit, pdu);
}

void ClientExaminer::answer_pipeline(std::size_t connection, Clock::time_point now) {
    auto& waiting = connections_[connection]->outstanding;
    // TCPG 4.4.1.1: answers are paired by transaction id, so their order is the server's choice.
    auto at = now;
    for (auto it = waiting.rbegin(); it != waiting.rend(); ++it) {
        answer(requests_[*it], right(requests_[*it]), false, at);
        at += kSegmentGap / 3;
    }
    waiting.clear();
}

}  // namespace mblab::conformance
