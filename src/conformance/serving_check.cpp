#include "conformance/serving_check.hpp"

#include "client/hex_text.hpp"

namespace mblab::conformance {

namespace {

// Whether `answer` answers `sent` by its header: the same transaction id and protocol id 0 where
// the framing numbers requests; on a line, which pairs answers by order, the address asked.
bool paired(const protocol::AduHeader& sent, const protocol::AduHeader& answer) {
    if (sent.has_transaction())
        return answer.transaction_id == sent.transaction_id &&
               answer.protocol_id == protocol::kModbusProtocolId;
    return answer.unit == sent.unit;
}

}  // namespace

std::array<std::uint8_t, 5> known_good_read(std::uint16_t address) {
    return {0x03, static_cast<std::uint8_t>(address >> 8), static_cast<std::uint8_t>(address), 0x00,
            0x01};
}

bool answers_known_good(std::span<const std::uint8_t> pdu) {
    return pdu.size() == 4 && pdu[0] == 0x03 && pdu[1] == 0x02;
}

std::string ServingAnswer::detail() const {
    if (served == Served::Wrong) return client::hex_bytes(received.bytes);
    return received.detail.empty() ? "closed" : received.detail;
}

Exchange ServingAnswer::exchange(std::chrono::milliseconds waited) const {
    Exchange out;
    out.sent = sent;
    out.status = received.status;
    out.received = received.bytes;
    out.detail = received.detail;
    out.discarded = received.discarded;
    out.waited = waited;
    return out;
}

std::vector<std::uint8_t> serving_read(const ServingQuestion& question) {
    const auto pdu = known_good_read(question.address);
    std::vector<std::uint8_t> frame(protocol::adu_size(question.header.framing, pdu.size()));
    frame.resize(protocol::write_adu(question.header, pdu, frame));
    return frame;
}

bool settles(const ServingQuestion& question, ServingAnswer& answer) {
    const auto& got = answer.received;
    switch (got.status) {
        case client::ReceiveStatus::Timeout:
            answer.served = Served::Silent;
            return true;
        case client::ReceiveStatus::Closed:
            answer.served = Served::Closed;
            return true;
        case client::ReceiveStatus::Frame:
            if (question.any_answer ||
                (paired(question.header, got.header) && answers_known_good(got.pdu))) {
                answer.served = Served::Yes;
                if (answers_known_good(got.pdu))
                    answer.value = static_cast<std::uint16_t>(got.pdu[2] << 8 | got.pdu[3]);
                return true;
            }
            break;
        case client::ReceiveStatus::Malformed:
            break;
    }
    answer.served = Served::Wrong;
    return question.any_answer || question.header.has_transaction();
}

}  // namespace mblab::conformance
