#include "conformance/tls_probe.hpp"

#include <fmt/core.h>

#include <filesystem>
#include <memory>

#include "client/hex_text.hpp"
#include "conformance/answer_rules.hpp"
#include "conformance/dut.hpp"
#include "conformance/pattern.hpp"
#include "conformance/serving_check.hpp"
#include "conformance/session.hpp"
#include "protocol/adu.hpp"
#include "protocol/adu_writer.hpp"
#include "protocol/mbap_header.hpp"

namespace mblab::conformance::tls_probe {

Outcome verdict(Verdict v, std::string reason, std::vector<Exchange> evidence) {
    return Outcome{v, std::move(reason), std::move(evidence)};
}

std::optional<Outcome> not_secure(const Session& session) {
    if (session.secure_target()) return std::nullopt;
    return verdict(Verdict::NotApplicable,
                   "a Modbus/TCP Security case: the device is not reached over mbaps:// (give an "
                   "mbaps:// target with --cert/--key/--ca or --pki DIR)");
}

// A client certificate of the declared PKI: DIR/NAME.pem and its key DIR/NAME.key.
security::TlsFiles pki_files(const Dut& dut, std::string_view name) {
    const std::filesystem::path dir = dut.security.pki;
    return {(dir / (std::string(name) + ".pem")).string(),
            (dir / (std::string(name) + ".key")).string(), dut.security.client.ca};
}

// N/A when a declaration the case needs was not given: `what` names it and its option.
std::optional<Outcome> undeclared(const std::string& value, const Needed& needed) {
    if (!value.empty()) return std::nullopt;
    auto outcome = verdict(Verdict::NotApplicable,
                           fmt::format("the DUT does not declare {} ({})", needed.key, needed.how));
    outcome.undeclared = std::string(needed.key);
    return outcome;
}

// N/A when the certificate the case needs was not declared: a PKI without that file.
std::optional<Outcome> missing(const security::TlsFiles& files) {
    std::error_code ignored;
    for (const auto* file : {&files.cert, &files.key}) {
        if (!std::filesystem::is_regular_file(*file, ignored)) {
            return verdict(
                Verdict::NotApplicable,
                fmt::format("the declared PKI has no {} (mblab pki DIR makes one)", *file));
        }
    }
    return std::nullopt;
}

// Connects to the device's mbaps:// port and runs the handshake with `files`. `verify` checks
// the device's certificate against the CA (chain and validity, not the name: [SEC] does not make
// the name a requirement); the cases that examine the device's handling of a bad client
// certificate do not, so that only the device decides.
Attempt open_tls(const Session& session, const security::TlsFiles& files,
                 security::ClientVersions versions, bool verify) {
    Attempt attempt;
    auto context = security::make_client_context(files, {versions, verify});
    if (!context) {
        attempt.error.message = context.error();
        attempt.local = true;
        return attempt;
    }
    const client::Target& target = *session.secure_target();
    client::Endpoint endpoint{
        target.tcp->host, target.tcp->port,
        std::make_shared<const client::TlsSetup>(client::TlsSetup{std::move(*context), ""})};
    auto link = client::RawLink::connect(endpoint, session.options().connect_timeout);
    if (!link) {
        attempt.error = link.error();
        return attempt;
    }
    attempt.link.emplace(std::move(link.value()));
    return attempt;
}

// NOT RUN for an attempt that failed before the device could judge it; nothing when the device
// refused the handshake, or let it fail (an error that names TLS, a timeout among them), which
// the security cases judge as a refusal.
std::optional<Outcome> not_judged(const Attempt& attempt) {
    if (attempt.local) {
        return verdict(Verdict::NotRun, "cannot make the TLS client: " + attempt.error.message);
    }
    if (attempt.link || attempt.error.tls_refused) return std::nullopt;
    if (attempt.error.message.find("TLS") == std::string::npos) {
        return verdict(Verdict::NotRun, "cannot connect to the device: " + attempt.error.message);
    }
    return std::nullopt;
}

Bytes mbap(std::uint16_t transaction, std::uint8_t unit, const Bytes& pdu) {
    Bytes out(protocol::adu_size(protocol::Framing::Mbap, pdu.size()));
    protocol::write_adu({protocol::Framing::Mbap, unit, transaction, 0}, pdu, out);
    return out;
}

Bytes read_register_zero(std::uint16_t transaction, std::uint8_t unit) {
    return mbap(transaction, unit, {0x03, 0x00, 0x00, 0x00, 0x01});
}

Bytes read_role_register(std::uint16_t transaction, std::uint8_t unit) {
    return mbap(transaction, unit, {0x03, 0x00, kRoleRegister, 0x00, 0x01});
}

Exchange ask(client::RawLink& link, const Bytes& request, std::chrono::milliseconds timeout) {
    Exchange exchange;
    exchange.sent = request;
    exchange.waited = timeout;
    exchange.on_connection = 1;
    client::LinkError error;
    if (!link.send(request, error)) {
        exchange.status = client::ReceiveStatus::Closed;
        exchange.detail = "cannot send: " + error.message;
        return exchange;
    }
    auto received = link.receive_frame(timeout);
    exchange.status = received.status;
    exchange.received = std::move(received.bytes);
    exchange.detail = std::move(received.detail);
    return exchange;
}

// The PDU of a request the tester wrote.
std::span<const std::uint8_t> request_pdu(const Bytes& request) {
    return protocol::read_mbap_frame(request)->pdu;
}

// The PDU of a whole answer to the request: its transaction id, protocol id 0, unit and function
// code (plain or exception); empty when what came is not one.
std::span<const std::uint8_t> answer_pdu(const Exchange& e) {
    if (e.status != client::ReceiveStatus::Frame) return {};
    const auto asked = protocol::read_mbap_frame(e.sent);
    const auto got = protocol::read_mbap_frame(e.received);
    if (!asked || !got || got->pdu.empty() ||
        got->header.transaction_id != asked->header.transaction_id ||
        got->header.protocol_id != protocol::kModbusProtocolId ||
        got->header.unit != asked->header.unit || (got->pdu[0] & 0x7F) != asked->pdu[0]) {
        return {};
    }
    return got->pdu;
}

bool answered(const Exchange& e) {
    return !answer_pdu(e).empty();
}

std::optional<std::uint8_t> exception_code(const Exchange& e) {
    const auto pdu = answer_pdu(e);
    if (pdu.size() != 2 || (pdu[0] & 0x80) == 0) return std::nullopt;
    return pdu[1];
}

// A normal answer whose fields are as [APP] fixes them.
bool data_answer(const Exchange& e) {
    const auto pdu = answer_pdu(e);
    if (pdu.empty() || (pdu[0] & 0x80) != 0) return false;
    return !answer_rule_broken(request_pdu(e.sent), pdu);
}

// The register an FC 03 read of one register answered (its data answer checked first).
std::pair<std::uint8_t, std::uint8_t> register_read(const Exchange& read) {
    const auto pdu = answer_pdu(read);  // function, byte count 2, the value
    return {pdu[2], pdu[3]};
}

// What the device did with a request, in a few words.
std::string what_came(const Exchange& e) {
    switch (e.status) {
        case client::ReceiveStatus::Frame:
            if (auto code = exception_code(e)) return fmt::format("exception {:02X}", *code);
            return "answered " + client::hex_bytes(e.received);
        case client::ReceiveStatus::Timeout:
            return fmt::format("no answer within {} ms", e.waited.count());
        case client::ReceiveStatus::Closed:
            return "the session ended" + (e.detail.empty() ? std::string() : " (" + e.detail + ")");
        case client::ReceiveStatus::Malformed:
            return "bytes that are no MBAP frame: " + client::hex_bytes(e.received);
    }
    return {};
}

// "a fatal alert handshake failure", for the reason of a refusal.
std::string refusal_text(const client::RawLink* link, const client::LinkError& error) {
    if (link != nullptr && link->tls_alert().received) {
        return "the device sent the alert '" + link->tls_alert().text + "'";
    }
    return error.message;
}

// After a case that disturbed the device: a session with the tester's own certificate must still
// be made and the serving check's read answered on it (any whole answer: the register need not
// exist). The reason it failed, or nothing.
std::optional<std::string> no_longer_serves(const Session& session) {
    auto attempt =
        open_tls(session, session.dut().security.client, security::ClientVersions::Modern, false);
    if (!attempt.link) {
        return "afterwards a session with the tester's own certificate failed: " +
               attempt.error.message;
    }
    const auto timeout = session.options().timeout;
    const auto answer = ask_serving(
        *attempt.link, {.header = {protocol::Framing::Mbap, session.dut().unit, 0x5EFF, 0},
                        .timeout = timeout,
                        .any_answer = true});
    if (answer.served == Served::Yes) return std::nullopt;
    return "afterwards a read on a new session got " + what_came(answer.exchange(timeout));
}
}  // namespace mblab::conformance::tls_probe
