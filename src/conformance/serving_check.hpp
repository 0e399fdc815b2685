#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "client/link_types.hpp"
#include "conformance/verdict.hpp"
#include "protocol/adu.hpp"

// Does the device still serve? After something that may have brought it down (a close a case
// allowed, a refused TLS handshake, a fuzz case) a plain read is asked, and its answer decides.
// Where it is asked (a new connection, a new TLS session, a connection opened before the case)
// and how often is each caller's policy; what is sent, how long it waits and which answer shows a
// device serving is here, once, for the conformance engine, the security suite and the robustness
// tester's liveness oracle.
namespace mblab::conformance {

// The known-good read: FC 03 of one register at `address`.
std::array<std::uint8_t, 5> known_good_read(std::uint16_t address);
// Whether `pdu` is its data answer: FC 03 with the one register.
bool answers_known_good(std::span<const std::uint8_t> pdu);

enum class Served : std::uint8_t {
    Yes,     // the answer came
    Closed,  // the link closed, or could not carry the read
    Silent,  // nothing came within the timeout
    Wrong,   // something else came in the answer's place
};

struct ServingQuestion {
    protocol::AduHeader header;  // framing, unit and transaction id of the read
    std::uint16_t address = 0;
    std::chrono::milliseconds timeout{1000};
    // Any whole frame shows the device serving, an exception as well as data, paired or not: a
    // device need not have register `address`. Otherwise only the register's data answer, paired
    // with the read by transaction id (by address on a line).
    bool any_answer = false;
    std::function<std::chrono::steady_clock::time_point()> now = [] {
        return std::chrono::steady_clock::now();
    };
};

struct ServingAnswer {
    Served served = Served::Silent;
    std::vector<std::uint8_t> sent;  // the read as written on the link
    client::Received received;       // what came last; Closed with why when it could not be sent
    std::uint16_t value = 0;         // the register, for a data answer

    // Closed: why ("closed" when nothing says); Wrong: what came, in hex.
    std::string detail() const;
    // The read and what came, as a case's evidence.
    Exchange exchange(std::chrono::milliseconds waited) const;
};

// The known-good read as `question.header` frames it.
std::vector<std::uint8_t> serving_read(const ServingQuestion& question);
// Takes what came into `answer` and whether it settles the question: not a frame that is not
// the answer on a line, which pairs answers by order, since it may be a late answer to the case.
bool settles(const ServingQuestion& question, ServingAnswer& answer);

// Sends the known-good read on `link` and waits for its answer. Any link that sends bytes and
// hands back whole frames will do: a client::Link, a client::RawLink, a session.
template <class FrameLink>
ServingAnswer ask_serving(FrameLink& link, const ServingQuestion& question) {
    ServingAnswer out;
    out.sent = serving_read(question);
    client::LinkError error;
    if (!link.send(out.sent, error)) {
        out.served = Served::Closed;
        out.received = client::Received(client::ReceiveStatus::Closed, {}, error.message);
        return out;
    }
    const auto deadline = question.now() + question.timeout;
    while (true) {
        const auto left =
            std::chrono::duration_cast<std::chrono::milliseconds>(deadline - question.now());
        if (left.count() <= 0) {
            out.served = Served::Silent;
            return out;
        }
        out.received = link.receive_frame(left);
        if (settles(question, out)) return out;
    }
}

}  // namespace mblab::conformance
