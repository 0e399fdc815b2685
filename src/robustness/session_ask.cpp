#include "robustness/session_ask.hpp"

#include "robustness/fuzz_case.hpp"

namespace mblab::robustness {

Ask session_ask(conformance::Session& session, std::chrono::milliseconds timeout) {
    return
        [&session, timeout, transaction = std::uint16_t{0}](
            std::uint8_t unit,
            std::span<const std::uint8_t> pdu) mutable -> std::optional<std::vector<std::uint8_t>> {
            client::LinkError lost;
            if (!session.reconnect(lost)) return std::nullopt;
            if (!session.send(mbap_frame(++transaction, unit, pdu), 1, lost)) return std::nullopt;
            auto answer = session.receive_frame(timeout);
            if (answer.status != client::ReceiveStatus::Frame) {
                session.close();
                return std::nullopt;
            }
            return answer.pdu;
        };
}

}  // namespace mblab::robustness
