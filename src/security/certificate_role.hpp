#pragma once

#include <openssl/types.h>

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

// The Modbus/TCP Security role of a certificate: [SEC] carries it in an X.509v3 extension whose
// value is one UTF8String. The server reads it once per TLS session, from the client's leaf
// certificate, and authorizes every request of that session by it.
namespace mblab::security {

inline constexpr std::string_view kRoleOid = "1.3.6.1.4.1.50316.802.1";

struct RoleReading {
    enum class Kind : std::uint8_t {
        None,     // no role extension: the NULL role, which no rule grants anything
        Role,     // exactly one role, in `role`
        Refused,  // more than one role, a value that is not a UTF8String, or a malformed value
    };
    Kind kind = Kind::None;
    std::string role;  // when Role
    std::string
        reason;  // when Refused: one line, e.g. "the role is an IA5String, not a UTF8String"
};

// Reads the role extension of `certificate` (not null).
RoleReading read_role(const X509* certificate);
// The same from a DER-encoded certificate; a certificate that does not parse is Refused.
RoleReading read_role_der(std::span<const std::uint8_t> der);

}  // namespace mblab::security
