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

#include "client/hex_text.hpp"
#include "client/raw_link.hpp"
#include "conformance/answer_rules.hpp"
#include "conformance/catalogue.hpp"
#include "conformance/pattern.hpp"
#include "conformance/plain_requests.hpp"
#include "conformance/session.hpp"
#include "conformance/tls_probe.hpp"
#include "protocol/adu.hpp"
#include "protocol/mbap_header.hpp"
#include "security/tls_channel.hpp"
#include "security/tls_context.hpp"

namespace mblab::conformance {

namespace {

using namespace tls_probe;
using security::ClientVersions;

constexpr std::uint8_t kIllegalFunction = 0x01;

// A session with the tester's own certificate, as `versions` allow; the outcome when the case
// cannot be judged (N/A off mbaps://, NOT RUN when the attempt failed on this side).
std::optional<Outcome> open_as_tester(Session& session, ClientVersions versions, bool verify_device,
                                      Attempt& attempt) {
    if (auto na = not_secure(session)) return *na;
    attempt = open_tls(session, session.dut().security.client, versions, verify_device);
    return not_judged(attempt);
}

Outcome refuse_old_version(Session& session, ClientVersions versions, std::string_view name) {
    Attempt attempt;
    if (auto stop = open_as_tester(session, versions, false, attempt)) return *stop;
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
                                                const Needed& declaration,
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

Outcome run_tls_handshake(Session& session, const Case&) {
    Attempt attempt;
    if (auto stop = open_as_tester(session, ClientVersions::Modern, true, attempt)) return *stop;
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
    auto opened = read_as_role(session, role, {"read_only_role", "--read-only-role NAME"}, 0x5E30);
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
    auto opened = read_as_role(session, role, {"write_role", "--write-role NAME"}, 0x5E40);
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
    Attempt attempt;
    if (auto stop = open_as_tester(session, ClientVersions::Tls12, false, attempt)) return *stop;
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
                           client::hex_bytes(reply.bytes));
    }
    if (auto dead = no_longer_serves(session)) {
        return verdict(Verdict::Fail, how + "; " + *dead, std::move(evidence));
    }
    return verdict(Verdict::Pass, how +
                                      "; RFC 5746 indication present; the device serves new "
                                      "sessions");
}

Outcome run_tls_close_notify(Session& session, const Case&) {
    Attempt attempt;
    if (auto stop = open_as_tester(session, ClientVersions::Modern, false, attempt)) return *stop;
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

// A security procedure opens TLS sessions of its own to the device's mbaps:// port.
ProcedureInfo tls_procedure(std::string_view name, std::string_view summary,
                            Outcome (*run)(Session&, const Case&)) {
    return ProcedureInfo{name, summary, {}, {}, false, run, nullptr, true};
}

}  // namespace

std::vector<ProcedureInfo> security_procedures() {
    return {
        tls_procedure(
            "tls_handshake",
            "[SEC] handshake with the tester's certificate (TLS 1.2+, mutual authentication, the "
            "device's certificate verified against the CA), then an FC 03 read answered inside TLS",
            &run_tls_handshake),
        tls_procedure("tls10_refused", "a TLS 1.0-only ClientHello is refused (R-34)",
                      &run_tls10_refused),
        tls_procedure("tls11_refused", "a TLS 1.1-only ClientHello is refused (R-34)",
                      &run_tls11_refused),
        tls_procedure(
            "no_certificate_refused",
            "a client that sends no certificate is refused with a fatal alert (R-10, R-44)",
            &run_no_certificate_refused),
        tls_procedure("expired_certificate_refused",
                      "the PKI's client-expired certificate is refused (R-06, R-47)",
                      &run_expired_certificate_refused),
        tls_procedure("foreign_ca_certificate_refused",
                      "the PKI's client-foreign-ca certificate is refused (R-06)",
                      &run_foreign_ca_certificate_refused),
        tls_procedure("self_signed_certificate_refused",
                      "the PKI's client-self-signed certificate is refused (R-06)",
                      &run_self_signed_certificate_refused),
        tls_procedure("null_role_denied",
                      "the PKI's client-norole certificate: every public function code answered "
                      "exception 01 (R-23, R-31)",
                      &run_null_role_denied),
        tls_procedure("read_only_role",
                      "the declared read-only role: FC 03 of register 0x0010 answered with data, "
                      "FC 06 and FC 10 answered exception 01 (R-04, R-30, R-31)",
                      &run_read_only_role),
        tls_procedure(
            "write_role",
            "the declared write role: FC 03 and FC 06 of register 0x0010 answered (R-04, R-30)",
            &run_write_role),
        tls_procedure("tls_renegotiation",
                      "TLS 1.2 session: the RFC 5746 indication present (R-60); a renegotiation "
                      "request leaves the device serving",
                      &run_tls_renegotiation),
        tls_procedure("tls_close_notify",
                      "close_notify after a read: the device ends the session and serves new ones",
                      &run_tls_close_notify),
    };
}

}  // namespace mblab::conformance
