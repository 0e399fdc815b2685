#include "conformance/security_cases.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <variant>
#include <vector>

#include "client/raw_link.hpp"
#include "conformance/answer_rules.hpp"
#include "conformance/catalogue.hpp"
#include "conformance/pattern.hpp"
#include "conformance/plain_requests.hpp"
#include "conformance/procedures.hpp"
#include "conformance/session.hpp"
#include "protocol/adu.hpp"
#include "protocol/mbap_header.hpp"
#include "security/tls_channel.hpp"
#include "security/tls_context.hpp"

namespace mblab::conformance {

namespace {

using Bytes = std::vector<std::uint8_t>;
using security::ClientVersions;

constexpr std::uint8_t kIllegalFunction = 0x01;

Outcome verdict(Verdict v, std::string reason, std::vector<Exchange> evidence = {}) {
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
std::optional<Outcome> undeclared(const std::string& value, std::string_view what) {
    if (!value.empty()) return std::nullopt;
    return verdict(Verdict::NotApplicable, fmt::format("the DUT does not declare {}", what));
}

constexpr std::string_view kPkiDeclaration =
    "pki (--pki DIR: client certificates as mblab pki "
    "writes them)";

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

struct Attempt {
    std::optional<client::RawLink> link;
    client::LinkError error;
    bool local = false;  // this side could not make its TLS context: nothing was tried
};

// Connects to the device's mbaps:// port and runs the handshake with `files`. `verify` checks
// the device's certificate against the CA (chain and validity, not the name: [SEC] does not make
// the name a requirement); the cases that examine the device's handling of a bad client
// certificate do not, so that only the device decides.
Attempt open_tls(const Session& session, const security::TlsFiles& files, ClientVersions versions,
                 bool verify) {
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
// refused the handshake (or timed it out, which `silence_refuses` accepts as a refusal).
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

// The role cases read and write holding register 0x0010, where the policy's write cases write
// (seed 000 7.8.1): a device that passes the policy has it writable.
constexpr std::uint8_t kRoleRegister = 0x10;

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
        got->header.protocol_id != 0 || got->header.unit != asked->header.unit ||
        (got->pdu[0] & 0x7F) != asked->pdu[0]) {
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
            return "answered " + hex_text(e.received);
        case client::ReceiveStatus::Timeout:
            return fmt::format("no answer within {} ms", e.waited.count());
        case client::ReceiveStatus::Closed:
            return "the session ended" + (e.detail.empty() ? std::string() : " (" + e.detail + ")");
        case client::ReceiveStatus::Malformed:
            return "bytes that are no MBAP frame: " + hex_text(e.received);
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
// be made and its read answered. The reason it failed, or nothing.
std::optional<std::string> no_longer_serves(const Session& session) {
    auto attempt = open_tls(session, session.dut().security.client, ClientVersions::Modern, false);
    if (!attempt.link) {
        return "afterwards a session with the tester's own certificate failed: " +
               attempt.error.message;
    }
    auto e = ask(*attempt.link, read_register_zero(0x5EFF, session.dut().unit),
                 session.options().timeout);
    if (!answered(e)) return "afterwards a read on a new session got " + what_came(e);
    return std::nullopt;
}

Outcome refuse_old_version(Session& session, ClientVersions versions, std::string_view name) {
    if (auto na = not_secure(session)) return *na;
    auto attempt = open_tls(session, session.dut().security.client, versions, false);
    if (auto stop = not_judged(attempt)) return *stop;
    if (attempt.link) {
        const auto& peer = attempt.link->tls()->peer();
        return verdict(Verdict::Fail,
                       fmt::format("the device completed a {} handshake ({} {}); R-34: no "
                                   "fallback to TLS 1.1 or older",
                                   name, peer.version, peer.cipher));
    }
    std::string how = attempt.error.tls_refused
                          ? refusal_text(nullptr, attempt.error)
                          : "it did not complete the handshake: " + attempt.error.message;
    if (auto dead = no_longer_serves(session)) return verdict(Verdict::Fail, *dead);
    return verdict(Verdict::Pass, fmt::format("{} refused: {}", name, how));
}

// A client certificate the device must refuse ([SEC]; chain and validity by
// RFC 5280, R-47): the handshake fails, or, in TLS 1.3 where the client finishes first, the
// device ends the session before answering anything.
Outcome refuse_certificate(Session& session, const security::TlsFiles& files,
                           std::string_view what) {
    if (auto na = not_secure(session)) return *na;
    if (!files.cert.empty()) {
        if (auto na = undeclared(session.dut().security.pki, kPkiDeclaration)) return *na;
        if (auto na = missing(files)) return *na;
    }
    auto attempt = open_tls(session, files, ClientVersions::Modern, false);
    if (auto stop = not_judged(attempt)) return *stop;
    if (!attempt.link) {
        const std::string how = attempt.error.tls_refused
                                    ? attempt.error.message
                                    : "the handshake did not complete: " + attempt.error.message;
        if (auto dead = no_longer_serves(session)) return verdict(Verdict::Fail, *dead);
        return verdict(Verdict::Pass, fmt::format("refused in the handshake: {}", how));
    }
    auto e = ask(*attempt.link, read_register_zero(0x5E01, session.dut().unit),
                 session.options().timeout);
    if (e.status == client::ReceiveStatus::Closed) {
        if (auto dead = no_longer_serves(session)) return verdict(Verdict::Fail, *dead);
        return verdict(Verdict::Pass, fmt::format("refused once the handshake was over: {}",
                                                  refusal_text(&*attempt.link, {e.detail})));
    }
    const auto& peer = attempt.link->tls()->peer();
    std::string reason =
        e.status == client::ReceiveStatus::Timeout
            ? fmt::format(
                  "the device kept a {} session open for a client with {} and did not "
                  "end it within {} ms; it must refuse the certificate with a fatal alert "
                  "and close",
                  peer.version, what, e.waited.count())
            : fmt::format("the device accepted a client with {} ({} {}) and it got {}", what,
                          peer.version, peer.cipher, what_came(e));
    return verdict(Verdict::Fail, std::move(reason), {e});
}

// The plain request of each public function code: a client without rights must get exception 01
// for every one.
std::vector<Bytes> every_function(std::uint8_t unit) {
    std::vector<Bytes> out;
    std::uint16_t transaction = 0x5E10;
    for (std::uint8_t function : functions_with_plain_requests()) {
        out.push_back(mbap(transaction++, unit, *plain_request_pdu(function)));
    }
    return out;
}

// Opens a session with a role's certificate; the outcome when it cannot.
std::optional<Outcome> open_role(Session& session, const security::TlsFiles& files,
                                 std::string_view role, Attempt& attempt) {
    if (auto na = undeclared(session.dut().security.pki, kPkiDeclaration)) return *na;
    if (auto na = missing(files)) return *na;
    attempt = open_tls(session, files, ClientVersions::Modern, false);
    if (auto stop = not_judged(attempt)) return *stop;
    if (!attempt.link) {
        return verdict(Verdict::Fail,
                       fmt::format("the device refused the handshake of a valid certificate with "
                                   "{}: {}",
                                   role, attempt.error.message));
    }
    return std::nullopt;
}

// A session as a declared role (client-ROLE in the PKI) whose read of the role register the
// declaration allows: the session and the value read, or the outcome when there is none (N/A,
// NOT RUN, or FAIL when the device refuses the handshake or the read).
struct RoleSession {
    Attempt attempt;
    std::uint8_t hi = 0;
    std::uint8_t lo = 0;
};

std::variant<Outcome, RoleSession> read_as_role(Session& session, const std::string& role,
                                                std::string_view declaration,
                                                std::uint16_t transaction) {
    if (auto na = not_secure(session)) return *na;
    if (auto na = undeclared(role, declaration)) return *na;
    RoleSession out;
    if (auto done = open_role(session, pki_files(session.dut(), "client-" + role), "role " + role,
                              out.attempt)) {
        return *done;
    }
    auto read = ask(*out.attempt.link, read_role_register(transaction, session.dut().unit),
                    session.options().timeout);
    if (!data_answer(read)) {
        return verdict(Verdict::Fail,
                       fmt::format("role {} may read holding register 0x0010 as declared, and its "
                                   "read got {}",
                                   role, what_came(read)),
                       {read});
    }
    std::tie(out.hi, out.lo) = register_read(read);
    return out;
}

}  // namespace

Outcome run_tls_handshake(Session& session, const Case&) {
    if (auto na = not_secure(session)) return *na;
    const auto& files = session.dut().security.client;
    auto attempt = open_tls(session, files, ClientVersions::Modern, true);
    if (auto stop = not_judged(attempt)) return *stop;
    if (!attempt.link) {
        return verdict(Verdict::Fail, "the handshake with the tester's certificate failed: " +
                                          attempt.error.message);
    }
    const auto& peer = attempt.link->tls()->peer();
    auto e = ask(*attempt.link, read_register_zero(0x5E00, session.dut().unit),
                 session.options().timeout);
    if (!answered(e)) {
        return verdict(Verdict::Fail,
                       fmt::format("the session was made ({} {}) but a read of holding register 0 "
                                   "got {}; R-05: MBAP goes unchanged inside TLS",
                                   peer.version, peer.cipher, what_came(e)),
                       {e});
    }
    if (auto broken = answer_rule_broken(request_pdu(e.sent), answer_pdu(e))) {
        return verdict(Verdict::Fail, *broken, {e});
    }
    const auto& role = peer.own_role;
    const std::string role_text = role.kind == security::RoleReading::Kind::Role
                                      ? "role " + role.role
                                      : std::string("no role");
    return verdict(Verdict::Pass,
                   fmt::format("{} {}, device {}, tester's certificate with {}; read answered {}",
                               peer.version, peer.cipher, peer.subject, role_text,
                               exception_code(e) ? what_came(e) : std::string("with data")));
}

Outcome run_tls10_refused(Session& session, const Case&) {
    return refuse_old_version(session, ClientVersions::Tls10, "TLS 1.0");
}

Outcome run_tls11_refused(Session& session, const Case&) {
    return refuse_old_version(session, ClientVersions::Tls11, "TLS 1.1");
}

Outcome run_no_certificate_refused(Session& session, const Case&) {
    security::TlsFiles none;
    none.ca = session.dut().security.client.ca;
    return refuse_certificate(session, none, "no certificate");
}

Outcome run_expired_certificate_refused(Session& session, const Case&) {
    return refuse_certificate(session, pki_files(session.dut(), "client-expired"),
                              "an expired certificate");
}

Outcome run_foreign_ca_certificate_refused(Session& session, const Case&) {
    return refuse_certificate(session, pki_files(session.dut(), "client-foreign-ca"),
                              "a certificate from another CA");
}

Outcome run_self_signed_certificate_refused(Session& session, const Case&) {
    return refuse_certificate(session, pki_files(session.dut(), "client-self-signed"),
                              "a self-signed certificate");
}

Outcome run_null_role_denied(Session& session, const Case&) {
    if (auto na = not_secure(session)) return *na;
    if (session.dut().security.null_role_granted) {
        return verdict(Verdict::NotApplicable,
                       "the DUT declares null_role_granted: its rights database gives the NULL "
                       "role rights");
    }
    Attempt attempt;
    if (auto done = open_role(session, pki_files(session.dut(), "client-norole"),
                              "no role (R-23: the NULL role)", attempt)) {
        return *done;
    }
    std::size_t asked = 0;
    for (const auto& request : every_function(session.dut().unit)) {
        auto e = ask(*attempt.link, request, session.options().timeout);
        ++asked;
        if (exception_code(e) == kIllegalFunction) continue;
        return verdict(Verdict::Fail,
                       fmt::format("function {:02X} from a client without a role got {}; R-23, "
                                   "R-31: the NULL role's refused request is answered exception "
                                   "01",
                                   request_pdu(request)[0], what_came(e)),
                       {e});
    }
    return verdict(Verdict::Pass,
                   fmt::format("{} function codes, each answered exception 01", asked));
}

Outcome run_read_only_role(Session& session, const Case&) {
    const std::string& role = session.dut().security.read_only_role;
    auto opened = read_as_role(session, role, "read_only_role (--read-only-role NAME)", 0x5E30);
    if (auto* done = std::get_if<Outcome>(&opened)) return std::move(*done);
    auto& [attempt, hi, lo] = std::get<RoleSession>(opened);
    // The writes put back what was read, so a device that wrongly obeys loses nothing.
    const std::uint8_t unit = session.dut().unit;
    const std::array<Bytes, 2> writes = {
        mbap(0x5E31, unit, {0x06, 0x00, kRoleRegister, hi, lo}),
        mbap(0x5E32, unit, {0x10, 0x00, kRoleRegister, 0x00, 0x01, 0x02, hi, lo}),
    };
    for (const auto& write : writes) {
        auto e = ask(*attempt.link, write, session.options().timeout);
        if (exception_code(e) == kIllegalFunction) continue;
        return verdict(Verdict::Fail,
                       fmt::format("role {} may not write, and its function {:02X} write got {}; "
                                   "R-31: a request its role may not make is answered exception 01",
                                   role, request_pdu(write)[0], what_came(e)),
                       {e});
    }
    return verdict(Verdict::Pass,
                   fmt::format("role {}: the read answered with data, writes with 06 and 10 "
                               "answered exception 01",
                               role));
}

Outcome run_write_role(Session& session, const Case&) {
    const std::string& role = session.dut().security.write_role;
    auto opened = read_as_role(session, role, "write_role (--write-role NAME)", 0x5E40);
    if (auto* done = std::get_if<Outcome>(&opened)) return std::move(*done);
    auto& [attempt, hi, lo] = std::get<RoleSession>(opened);
    auto write =
        ask(*attempt.link, mbap(0x5E41, session.dut().unit, {0x06, 0x00, kRoleRegister, hi, lo}),
            session.options().timeout);
    // FC 06 answers with an echo of the request's PDU.
    const auto echoed = answer_pdu(write);
    const auto asked = request_pdu(write.sent);
    if (!data_answer(write) ||
        !std::equal(echoed.begin(), echoed.end(), asked.begin(), asked.end())) {
        return verdict(Verdict::Fail,
                       fmt::format("role {} may write holding register 0x0010 as declared, and its "
                                   "function 06 write got {}",
                                   role, what_came(write)),
                       {write});
    }
    return verdict(
        Verdict::Pass,
        fmt::format("role {}: the read and the write of register 0x0010 were answered", role));
}

Outcome run_tls_renegotiation(Session& session, const Case&) {
    if (auto na = not_secure(session)) return *na;
    auto attempt = open_tls(session, session.dut().security.client, ClientVersions::Tls12, false);
    if (auto stop = not_judged(attempt)) return *stop;
    if (!attempt.link) {
        return verdict(Verdict::NotApplicable, "the device did not make a TLS 1.2 session (" +
                                                   attempt.error.message +
                                                   "): renegotiation exists in TLS 1.2 only");
    }
    client::RawLink& link = *attempt.link;
    if (!link.tls()->secure_renegotiation()) {
        return verdict(Verdict::Fail,
                       "the device's TLS 1.2 ServerHello lacks the renegotiation indication "
                       "(RFC 5746); R-60 requires it");
    }
    client::LinkError error;
    if (!link.renegotiate(error)) {
        return verdict(Verdict::NotRun, "cannot ask for a renegotiation: " + error.message);
    }
    // The device's reply to the new ClientHello comes before any answer: a read gives it the
    // time to come, and the renegotiation the time to finish.
    const auto waited = session.options().timeout;
    auto reply = link.receive_frame(waited);
    std::string how;
    std::vector<Exchange> evidence;
    if (reply.status == client::ReceiveStatus::Closed) {
        const auto& alert = link.tls_alert();
        how = alert.received && alert.description == security::TlsAlert::kNoRenegotiation
                  ? "the device refused with a no_renegotiation warning (and OpenSSL, this "
                    "side, ends a session whose renegotiation was refused)"
                  : "the device ended the session: " + refusal_text(&link, {reply.detail});
    } else if (reply.status == client::ReceiveStatus::Timeout) {
        auto e = ask(link, read_register_zero(0x5E50, session.dut().unit), waited);
        const auto& alert = link.tls_alert();
        const bool refused =
            alert.received && alert.description == security::TlsAlert::kNoRenegotiation;
        if (answered(e)) {
            how = refused ? "the device refused with a no_renegotiation warning and the session "
                            "went on: a read was answered"
                          : "the session went on: a read was answered";
        } else {
            how = "after the renegotiation request a read on the session got " + what_came(e);
            evidence.push_back(std::move(e));
        }
    } else {
        return verdict(Verdict::Fail,
                       "the device sent an unasked frame after the renegotiation request: " +
                           hex_text(reply.bytes));
    }
    if (auto dead = no_longer_serves(session)) {
        return verdict(Verdict::Fail, how + "; " + *dead, std::move(evidence));
    }
    return verdict(Verdict::Pass, how +
                                      "; RFC 5746 indication present; the device serves new "
                                      "sessions");
}

Outcome run_tls_close_notify(Session& session, const Case&) {
    if (auto na = not_secure(session)) return *na;
    auto attempt = open_tls(session, session.dut().security.client, ClientVersions::Modern, false);
    if (auto stop = not_judged(attempt)) return *stop;
    if (!attempt.link) {
        return verdict(Verdict::NotRun, "cannot make a session with the tester's certificate: " +
                                            attempt.error.message);
    }
    auto e = ask(*attempt.link, read_register_zero(0x5E60, session.dut().unit),
                 session.options().timeout);
    if (!answered(e)) {
        return verdict(Verdict::Fail, "a read before close_notify got " + what_came(e), {e});
    }
    std::string how;
    attempt.link->close_notify(session.options().timeout, how);
    attempt.link->close();
    if (auto dead = no_longer_serves(session)) {
        return verdict(Verdict::Fail, "after close_notify " + how + "; " + *dead);
    }
    return verdict(Verdict::Pass, "after close_notify " + how + "; the device serves new sessions");
}

bool is_security_procedure(std::string_view procedure) {
    const ProcedureInfo* info = find_procedure(procedure);
    return info != nullptr && info->needs_mbaps;
}

}  // namespace mblab::conformance
