// The role reader (Modbus/TCP Security) on any bytes as a DER certificate: must never crash nor
// leak, and its answer must be one of the three it promises: a non-empty role, the NULL role, or a
// refusal with a one-line reason.
//
// The seed corpus (fuzz/corpus/fuzz_certificate_role/) is certificates of `mblab pki` in DER,
// each converted by `openssl x509 -in NAME.pem -outform DER -out NAME.der`: client-Operator (a
// role), client-ia5-role, client-two-roles, client-norole and server (no role).
#include <cstdint>
#include <cstdlib>
#include <span>
#include <string>

#include "security/certificate_role.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using mblab::security::RoleReading;
    const RoleReading reading = mblab::security::read_role_der({data, size});
    switch (reading.kind) {
        case RoleReading::Kind::Role:
            if (reading.role.empty() || !reading.reason.empty()) std::abort();
            break;
        case RoleReading::Kind::None:
            if (!reading.role.empty() || !reading.reason.empty()) std::abort();
            break;
        case RoleReading::Kind::Refused:
            if (!reading.role.empty() || reading.reason.empty()) std::abort();
            if (reading.reason.find('\n') != std::string::npos) std::abort();
            break;
    }
    return 0;
}
