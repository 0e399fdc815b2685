#include "client/transactor.hpp"

#include <algorithm>
#include <array>
#include <utility>

#include "client/hex_text.hpp"
#include "client/tls_sniff.hpp"
#include "client/unit_probe.hpp"
#include "protocol/adu.hpp"
#include "protocol/framer.hpp"
#include "protocol/function_code.hpp"
#include "protocol/limits.hpp"
#include "support/name_table.hpp"

namespace mblab::client {

namespace {

using Clock = std::chrono::steady_clock;

// Room for the largest ADU of any framing (ASCII: 513 characters).
constexpr std::size_t kAduBuffer = 520;
// Answers a transaction may skip before its own: a device replaying old answers must not keep
// the client waiting past its deadline, and the deadline bounds this anyway.
constexpr std::size_t kMaxUnanswered = 64;

std::string function_text(std::uint8_t code) {
    return hex8(code) + " (" + std::string(protocol::function_name(code)) + ")";
}

std::string byte_count(std::size_t count) {
    return std::to_string(count) + (count == 1 ? " byte" : " bytes");
}

}  // namespace

const char* error_kind_name(ErrorKind kind) {
    static constexpr Named<ErrorKind, const char*> kNames[] = {
        {ErrorKind::Invalid, "invalid"},      {ErrorKind::Connect, "connect"},
        {ErrorKind::Timeout, "timeout"},      {ErrorKind::Closed, "closed"},
        {ErrorKind::BadAnswer, "bad-answer"}, {ErrorKind::Exception, "exception"}};
    return name_of(kNames, kind, "error");
}

Transactor::Transactor(std::string target, LinkOpener opener, TransactionOptions options,
                       FrameObserver* observer)
    : target_(std::move(target)),
      opener_(std::move(opener)),
      options_(options),
      observer_(observer) {}

protocol::Result<Done, ClientError> Transactor::connect() {
    return ensure_link();
}

protocol::Result<Done, ClientError> Transactor::ensure_link() {
    if (link_ && link_->is_open()) return Done{};
    link_.reset();
    unanswered_.clear();
    auto opened = opener_();
    if (!opened) {
        return ClientError{ErrorKind::Connect,
                           "cannot connect to " + target_ + ": " + opened.error().message,
                           std::nullopt};
    }
    link_ = std::move(opened.value());
    return Done{};
}

void Transactor::drop_link() {
    if (link_) link_->close();
    link_.reset();
    unanswered_.clear();
}

void Transactor::note(const std::string& text) {
    if (observer_ != nullptr) observer_->on_note(text);
}

Transactor::Failure Transactor::bad_answer(std::string message) {
    // After a frame that broke the rules, nothing later on the stream can be trusted to line up.
    drop_link();
    return {{ErrorKind::BadAnswer, "bad answer: " + std::move(message), std::nullopt}, false};
}

Transactor::Failure Transactor::lost(std::string message) {
    drop_link();
    return {{ErrorKind::Closed, std::move(message), std::nullopt}, true};
}

protocol::Result<std::uint16_t, Transactor::Failure> Transactor::send(
    std::span<const std::uint8_t> request) {
    if (auto linked = ensure_link(); !linked) return Failure{linked.error(), false};
    if (options_.unit == 0 && link_->framing() != Framing::Mbap) {
        // On a serial line address 0 is a broadcast: executed by every device, answered by none.
        return Failure{{ErrorKind::Invalid,
                        "unit 0 is the broadcast address of a serial line, which no device "
                        "answers; mblab does not send broadcasts",
                        std::nullopt},
                       false};
    }
    const std::uint16_t transaction_id = next_transaction_id_++;
    std::array<std::uint8_t, kAduBuffer> adu{};
    const std::size_t size =
        protocol::write_adu({link_->framing(), options_.unit, transaction_id}, request, adu);
    if (request.empty() || size == 0) {
        return Failure{
            {ErrorKind::Invalid,
             "a request of " + byte_count(request.size()) + " does not fit a frame", std::nullopt},
            false};
    }
    const auto bytes = std::span<const std::uint8_t>(adu).first(size);
    if (observer_ != nullptr) observer_->on_frame(FrameDirection::Sent, link_->framing(), bytes);
    LinkError error;
    if (!link_->send(bytes, error)) return lost("cannot send to " + target_ + ": " + error.message);
    return transaction_id;
}

protocol::Result<Done, ClientError> Transactor::send_only(std::span<const std::uint8_t> request) {
    auto sent = send(request);
    if (!sent) return sent.error().error;
    return Done{};
}

protocol::Result<std::vector<std::uint8_t>, ClientError> Transactor::transact(
    std::span<const std::uint8_t> request) {
    const unsigned tries = options_.retries + 1;
    for (unsigned attempt_number = 1;; ++attempt_number) {
        auto result = attempt(request);
        if (result) return std::move(result.value());
        Failure failure = result.error();
        if (!failure.retry || attempt_number == tries) {
            if (tries > 1 && failure.retry) {
                failure.error.message += " (" + std::to_string(tries) + " tries)";
            }
            if (failure.error.kind == ErrorKind::Timeout &&
                failure.error.message.starts_with("no answer")) {
                failure.error.message += unit_hint();
            }
            return failure.error;
        }
        note("retry " + std::to_string(attempt_number) + " of " + std::to_string(options_.retries) +
             " after: " + failure.error.message);
    }
}

std::string Transactor::unit_hint() {
    if (probed_ || !options_.probe_units) return {};
    probed_ = true;
    const std::uint8_t asked = options_.unit;
    const Framing framing = link_ ? link_->framing() : Framing::Mbap;
    const auto started = Clock::now();
    std::size_t probes = 0;
    auto hint = probe_units(framing, asked, [this, &probes](std::uint8_t unit) {
        ++probes;
        drop_link();
        options_.unit = unit;
        auto sent = send(kUnitProbePdu);
        return sent && await_answer(*sent, kUnitProbePdu[0]).ok();
    });
    options_.unit = asked;
    drop_link();
    // The probes' waits add to the command's time: say how much, and how to go without them.
    const auto took = std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - started);
    // When the unit asked answered the probe, nothing is said and little time went.
    if (hint.empty()) return hint;
    return hint + " (" + std::to_string(probes) +
           (probes == 1 ? " probe read, " : " probe reads, ") + std::to_string(took.count()) +
           " ms; --no-probe skips them)";
}

Transactor::Attempt Transactor::attempt(std::span<const std::uint8_t> request) {
    auto sent = send(request);
    if (!sent) return sent.error();
    return await_answer(*sent, request.front());
}

Transactor::Attempt Transactor::await_answer(std::uint16_t transaction_id, std::uint8_t function) {
    const auto deadline = Clock::now() + options_.timeout;
    discarded_.clear();
    while (true) {
        const auto left = std::max(Clock::duration::zero(), deadline - Clock::now());
        Received received =
            link_->receive_frame(std::chrono::duration_cast<std::chrono::milliseconds>(left));
        if (is_tls_answer_text(received.detail)) {
            // The port speaks TLS: asking again would get the same, so this is the whole error.
            drop_link();
            return Failure{{ErrorKind::BadAnswer, std::move(received.detail), std::nullopt}, false};
        }
        switch (received.status) {
            case ReceiveStatus::Frame:
                if (observer_ != nullptr) {
                    observer_->on_frame(FrameDirection::Received, link_->framing(), received.bytes);
                }
                if (auto judged = judge(received.bytes, transaction_id, function)) {
                    return std::move(*judged);
                }
                continue;
            case ReceiveStatus::Timeout: {
                const std::string within =
                    " within " + std::to_string(options_.timeout.count()) + " ms";
                if (!received.bytes.empty()) {
                    // The rest of that frame may still come and would put every later answer
                    // out of step: start again on a new connection.
                    drop_link();
                    return Failure{{ErrorKind::Timeout,
                                    "no complete answer from " + target_ + within + " (" +
                                        byte_count(received.bytes.size()) + " of a frame came)",
                                    std::nullopt},
                                   true};
                }
                if (unanswered_.size() < kMaxUnanswered) unanswered_.push_back(transaction_id);
                return Failure{
                    {ErrorKind::Timeout,
                     "no answer from " + target_ + " (unit " + std::to_string(options_.unit) + ")" +
                         within + (discarded_.empty() ? "" : "; discarded " + discarded_),
                     std::nullopt},
                    true};
            }
            case ReceiveStatus::Closed:
                // A TLS server that refuses our certificate after a TLS 1.3 handshake says why
                // in an alert that only arrives now.
                if (received.bytes.empty() && received.detail.starts_with("TLS: ")) {
                    return lost("the device ended the TLS session without answering: " +
                                received.detail.substr(5));
                }
                return lost(received.bytes.empty()
                                ? "the device closed the connection without answering"
                                : "the device closed the connection after " +
                                      byte_count(received.bytes.size()) + " of an answer");
            case ReceiveStatus::Malformed:
                if (observer_ != nullptr && !received.bytes.empty()) {
                    observer_->on_frame(FrameDirection::Received, link_->framing(), received.bytes);
                }
                return bad_answer(received.detail);
        }
    }
}

std::optional<Transactor::Attempt> Transactor::judge(std::span<const std::uint8_t> frame,
                                                     std::uint16_t transaction_id,
                                                     std::uint8_t function) {
    protocol::Framer framer({link_->framing()});
    const auto adu = framer.whole_frame(frame);
    if (!adu) return Attempt(bad_answer(adu.error()));
    const auto& header = adu->header;
    if (header.has_transaction() && header.transaction_id != transaction_id) {
        auto late = std::find(unanswered_.begin(), unanswered_.end(), header.transaction_id);
        if (late != unanswered_.end()) {
            unanswered_.erase(late);
            note("skipped a late answer to transaction " + hex16(header.transaction_id));
            return std::nullopt;
        }
        // TCPG 4.4.1.1: an answer that matches no pending transaction is discarded, and the
        // wait for this one goes on.
        discarded_ = "an answer under transaction id " + hex16(header.transaction_id) +
                     ", expected " + hex16(transaction_id);
        note("discarded " + discarded_);
        return std::nullopt;
    }
    if (header.unit != options_.unit) {
        // SER 2.4.1: an answer from another address leaves the response timer running; a
        // gateway's other unit over TCP likewise.
        discarded_ = "an answer from unit " + std::to_string(header.unit) + ", expected " +
                     std::to_string(options_.unit);
        note("discarded " + discarded_);
        return std::nullopt;
    }
    if (adu->pdu.empty()) {
        return Attempt(bad_answer(header.has_transaction()
                                      ? "MBAP length 1 leaves no room for a function code"
                                      : "the frame holds no function code"));
    }
    const std::uint8_t answered = adu->pdu.front();
    if (answered != function && answered != (function | protocol::kExceptionBit)) {
        return Attempt(bad_answer("function code is " + function_text(answered) + ", expected " +
                                  function_text(function)));
    }
    return Attempt(std::vector<std::uint8_t>(adu->pdu.begin(), adu->pdu.end()));
}

}  // namespace mblab::client
