#include "cli/tls_options.hpp"

#include <fmt/core.h>

namespace mblab::cli {

void add_tls_options(CLI::App& command, security::TlsFiles& files, const char* side) {
    command.add_option(
        "--cert", files.cert,
        fmt::format("mbaps://: the {} certificate (PEM), e.g. from mblab pki", side));
    command.add_option("--key", files.key, "mbaps://: the private key of --cert (PEM)");
    command.add_option("--ca", files.ca,
                       "mbaps://: the CA certificate (PEM) the peer's certificate must be "
                       "signed by");
}

std::string describe_tls(const security::TlsPeer& peer) {
    std::string role;
    switch (peer.own_role.kind) {
        case security::RoleReading::Kind::None:
            role = "no role";
            break;
        case security::RoleReading::Kind::Role:
            role = "role " + peer.own_role.role;
            break;
        case security::RoleReading::Kind::Refused:
            role = "an unreadable role (" + peer.own_role.reason + ")";
            break;
    }
    return fmt::format("{} {}{}, server {}, we presented {}", peer.version, peer.cipher,
                       peer.resumed ? " (resumed)" : "",
                       peer.subject.empty() ? "(no certificate)" : peer.subject, role);
}

}  // namespace mblab::cli
