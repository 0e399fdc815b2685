#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "client/raw_link.hpp"
#include "conformance/verdict.hpp"
#include "security/tls_context.hpp"

// What the security suite's cases share: TLS sessions of the tester's own to the device's
// mbaps:// port, the requests sent on them, and how what came back reads (answered, exception,
// data as [APP] fixes it, or silence), for the reasons and the evidence.
namespace mblab::conformance {

class Session;
struct Dut;

namespace tls_probe {

using Bytes = std::vector<std::uint8_t>;

Outcome verdict(Verdict v, std::string reason, std::vector<Exchange> evidence = {});

// N/A unless the device is reached over mbaps://.
std::optional<Outcome> not_secure(const Session& session);

// A client certificate of the declared PKI: DIR/NAME.pem and its key DIR/NAME.key.
security::TlsFiles pki_files(const Dut& dut, std::string_view name);

// A declaration a case needs: its DUT key, and how to give it.
struct Needed {
    std::string_view key;
    std::string_view how;
};

// N/A when a declaration the case needs was not given.
std::optional<Outcome> undeclared(const std::string& value, const Needed& needed);

inline constexpr Needed kPkiDeclaration{"pki",
                                        "--pki DIR: client certificates as mblab pki writes them"};

// N/A when the certificate the case needs was not declared: a PKI without that file.
std::optional<Outcome> missing(const security::TlsFiles& files);

struct Attempt {
    std::optional<client::RawLink> link;
    client::LinkError error;
    bool local = false;  // this side could not make its TLS context: nothing was tried
};

// Connects to the device's mbaps:// port and runs the handshake with `files`. `verify` checks
// the device's certificate against the CA (chain and validity, not the name: [SEC] does not make
// the name a requirement); the cases that examine the device's handling of a bad client
// certificate do not, so that only the device decides.
Attempt open_tls(const Session& session, const security::TlsFiles& files,
                 security::ClientVersions versions, bool verify);

// NOT RUN for an attempt that failed before the device could judge it; nothing when the device
// refused the handshake, or let it fail (an error that names TLS, a timeout among them), which
// the security cases judge as a refusal.
std::optional<Outcome> not_judged(const Attempt& attempt);

Bytes mbap(std::uint16_t transaction, std::uint8_t unit, const Bytes& pdu);
Bytes read_register_zero(std::uint16_t transaction, std::uint8_t unit);

// The role cases read and write holding register 0x0010, where the policy's write cases write
// (CTP 7.8.1): a device that passes the policy has it writable.
inline constexpr std::uint8_t kRoleRegister = 0x10;
Bytes read_role_register(std::uint16_t transaction, std::uint8_t unit);

Exchange ask(client::RawLink& link, const Bytes& request, std::chrono::milliseconds timeout);

// The PDU of a request the tester wrote.
std::span<const std::uint8_t> request_pdu(const Bytes& request);
// The PDU of a whole answer to the request: its transaction id, protocol id 0, unit and function
// code (plain or exception); empty when what came is not one.
std::span<const std::uint8_t> answer_pdu(const Exchange& e);
bool answered(const Exchange& e);
std::optional<std::uint8_t> exception_code(const Exchange& e);
// A normal answer whose fields are as [APP] fixes them.
bool data_answer(const Exchange& e);
// The register an FC 03 read of one register answered (its data answer checked first).
std::pair<std::uint8_t, std::uint8_t> register_read(const Exchange& read);
// What the device did with a request, in a few words.
std::string what_came(const Exchange& e);
// "a fatal alert handshake failure", for the reason of a refusal.
std::string refusal_text(const client::RawLink* link, const client::LinkError& error);
// After a case that disturbed the device: a session with the tester's own certificate must still
// be made and the serving check's read answered on it. The reason it failed, or nothing.
std::optional<std::string> no_longer_serves(const Session& session);

}  // namespace tls_probe
}  // namespace mblab::conformance
