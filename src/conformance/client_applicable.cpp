#include "conformance/client_applicable.hpp"

#include <string>

namespace mblab::conformance {

std::optional<Outcome> undeclared(const ClientCase& scenario, const ClientDeclarations& declared) {
    // The key stays empty: conform's summary would send the user to a DUT file; the reason
    // names the flag instead.
    auto na = [](std::string reason, std::string_view) {
        return Outcome{Verdict::NotApplicable, std::move(reason), {}, {}};
    };
    switch (scenario.scenario) {
        case ClientScenario::NoReply:
            if (!declared.timeout)
                return na("the client's timeout is not declared (--client-timeout)", "timeout");
            if (!declared.retries)
                return na("the client's retries are not declared (--client-retries)", "retries");
            return std::nullopt;
        case ClientScenario::LateReply:
            if (!declared.timeout)
                return na("the client's timeout is not declared (--client-timeout)", "timeout");
            if (declared.retries.value_or(0) == 0) {
                return na(
                    "needs --client-retries 1 or more: the stale answer must meet a later request",
                    "retries");
            }
            return std::nullopt;
        case ClientScenario::Pipelined:
            if (!declared.pipelining)
                return na("the client does not declare pipelining (--client-pipelining)",
                          "pipelining");
            return std::nullopt;
        case ClientScenario::Broadcast:
            if (!declared.broadcast)
                return na("the client does not declare broadcasts (--client-broadcast)",
                          "broadcast");
            if (!declared.timeout)
                return na("the client's timeout is not declared (--client-timeout)", "timeout");
            return std::nullopt;
        default:
            return std::nullopt;
    }
}

std::optional<Outcome> needs_output(const ClientCase& scenario) {
    const auto na = [](const char* reason) {
        return Outcome{Verdict::NotApplicable, std::string("--attach: ") + reason, {}, {}};
    };
    switch (scenario.scenario) {
        case ClientScenario::NoReply:
        case ClientScenario::Exception:
        case ClientScenario::CloseFin:
        case ClientScenario::CloseReset:
        case ClientScenario::Untrusted:
            return std::nullopt;
        case ClientScenario::Broadcast:
            return na("the client cannot be told to broadcast");
        case ClientScenario::Pipelined:
            return na("pipelining is judged by the order of the values the client shows");
        default:
            return na(
                "whether the client took the decoys shows only in its output, which an "
                "attached client does not give");
    }
}

}  // namespace mblab::conformance
