#include "conformance/client_exam_scenarios.hpp"

#include <fmt/core.h>

#include <string_view>

namespace mblab::conformance {

namespace {

// Scenario 6 of each transport: every exception code a client must take as an error.
void add_exception_cases(std::vector<ClientCase>& cases, std::string_view transport,
                         const std::string& source) {
    for (const std::uint8_t code : {0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x0A, 0x0B}) {
        cases.push_back({fmt::format("{}.6.{:02X}", transport, code),
                         fmt::format("exception {:02X} is an error, never a value", code), source,
                         ClientScenario::Exception, code});
    }
}

std::vector<ClientCase> make_cases() {
    // TCPG 4.4.1.1 is the client's side: how it builds requests, manages its timeout and
    // processes confirmations (an answer whose transaction id matches no pending transaction is
    // discarded).
    std::vector<ClientCase> cases = {
        {"tcp.1", "no reply: times out, retries as declared, then an error",
         "TCPG 4.4.1.1 (timeout management)", ClientScenario::NoReply},
        {"tcp.2", "a reply after the timeout is never taken for the next request",
         "TCPG 4.4.1.1; TCPG 3.1.3", ClientScenario::LateReply},
        {"tcp.3", "an answer under a wrong transaction id is discarded", "TCPG 4.4.1.1; TCPG 3.1.3",
         ClientScenario::WrongTransaction},
        {"tcp.4", "an answer from another unit is discarded, the wait goes on",
         "TCPG 3.1.3; SER 2.4.1", ClientScenario::WrongUnit},
        {"tcp.5.1", "an answer with another function code is rejected", "APP 6.3; TCPG 4.4.1.1",
         ClientScenario::WrongFunction},
        {"tcp.5.2", "a truncated answer is rejected", "APP 6.3; TCPG 3.1.3",
         ClientScenario::Truncated},
        {"tcp.5.3", "an answer with extra bytes is rejected", "APP 6.3; TCPG 3.1.3",
         ClientScenario::ExtraBytes},
    };
    add_exception_cases(cases, "tcp", "APP 7");
    cases.insert(
        cases.end(),
        {
            {"tcp.7.1", "an answer split over three segments is read whole", "TCPG 3.1.3",
             ClientScenario::SplitAnswer},
            {"tcp.7.2", "two answers in one segment: the client's own is taken", "TCPG 3.1.3",
             ClientScenario::TwoAnswers},
            {"tcp.8.1", "connection closed (FIN) mid-transaction: reconnects without a burst",
             "TCPG 4.2.1", ClientScenario::CloseFin},
            {"tcp.8.2", "connection reset mid-transaction: reconnects without a burst",
             "TCPG 4.2.1", ClientScenario::CloseReset},
            {"tcp.10", "a byte count that does not match the quantity is rejected", "APP 6.3",
             ClientScenario::ByteCount},
            {"tcp.11", "pipelined requests answered out of order are matched by transaction id",
             "TCPG 4.2.1.1; TCPG 4.4.1.1", ClientScenario::Pipelined},
        });
    return cases;
}

std::vector<ClientCase> make_line_cases() {
    // SER 2.4.1: the master's response timeout; an answer from another address is discarded and
    // the timer keeps running; a broadcast is answered by none and followed by a turnaround delay.
    std::vector<ClientCase> cases = {
        {"ser.1", "no reply: times out, retries as declared, then an error",
         "SER 2.4.1 (response time-out)", ClientScenario::NoReply},
        {"ser.4", "a reply from another slave address is discarded, the timer keeps running",
         "SER 2.4.1", ClientScenario::WrongUnit},
        {"ser.5", "an answer with a bad CRC or LRC is rejected and the client recovers",
         "SER 2.5.1.2; SER 2.5.2.2", ClientScenario::BadCheck},
    };
    add_exception_cases(cases, "ser", "APP 7; SER 2.4.1");
    cases.push_back({"ser.9", "broadcast: no wait for an answer, a turnaround delay after it",
                     "SER 2.2; SER 2.4.1", ClientScenario::Broadcast});
    return cases;
}

std::vector<ClientCase> make_mbaps_cases() {
    auto cases = make_cases();
    // SEC R-06: the peer's certificate is verified (RFC 5280 path and validity); [SEC] leaves the
    // name to the client, RFC 6125 says how a TLS client checks it.
    const auto untrusted = ClientScenario::Untrusted;
    cases.insert(
        cases.end(),
        {
            {"tls.12.1", "an expired server certificate is refused", "SEC R-06; RFC 5280 4.1.2.5",
             untrusted, 0, "server-expired", "that has expired"},
            {"tls.12.2", "a server certificate from an unknown CA is refused",
             "SEC R-06; RFC 5280 6.1", untrusted, 0, "server-foreign-ca", "from an unknown CA"},
            {"tls.12.3", "a server certificate naming another host is refused", "RFC 6125 6",
             untrusted, 0, "server-wrong-name", "naming wrong-name.invalid only"},
        });
    return cases;
}

}  // namespace

const std::vector<ClientCase>& client_mbaps_cases() {
    static const std::vector<ClientCase> cases = make_mbaps_cases();
    return cases;
}

const std::vector<ClientCase>& client_line_cases() {
    static const std::vector<ClientCase> cases = make_line_cases();
    return cases;
}

const std::vector<ClientCase>& client_tcp_cases() {
    static const std::vector<ClientCase> cases = make_cases();
    return cases;
}

}  // namespace mblab::conformance
