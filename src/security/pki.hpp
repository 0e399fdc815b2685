#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "protocol/result.hpp"

// A lab PKI for Modbus/TCP Security: a CA, a server certificate, a client certificate per role,
// the client certificates a conformant server must refuse or treat as the NULL role (no role,
// expired, from another CA, self-signed, two roles, a role that is not a UTF8String), and the
// server certificates a client must refuse (expired, from another CA, another name). Test
// material only: the keys are written unencrypted, and the CA key sits beside the certificates.
namespace mblab::security {

struct PkiRequest {
    enum class KeyType { Ec, Rsa };

    // One client-<role>.pem per role.
    std::vector<std::string> roles{"ReadOnly", "Operator", "Administrator"};
    // The server certificate's subjectAltName: IPv4 and IPv6 addresses as IP, the rest as DNS.
    std::vector<std::string> server_names{"localhost", "127.0.0.1", "::1"};
    int days = 365;
    // ECDSA P-256 is [SEC]'s ECC minimum; RSA 2048 for peers that take no EC keys.
    KeyType key_type = KeyType::Ec;
    // Replace files from an earlier run instead of refusing to.
    bool overwrite = false;
};

inline constexpr int kMaxPkiDays = 36500;

// Why `role` cannot be a role of make_lab_pki (it names a file and goes into a subject CN), or
// nullopt when it can.
std::optional<std::string> role_name_problem(const std::string& role);

// Writes the PKI into `dir` (made mode 0700 when missing), every file mode 0600, each certificate
// NAME.pem with its key NAME.key. Nothing is written unless every certificate could be made and
// no file exists already (or `overwrite`). Returns the files written, or one line saying why not.
protocol::Result<std::vector<std::filesystem::path>, std::string> make_lab_pki(
    const std::filesystem::path& dir, const PkiRequest& request);

}  // namespace mblab::security
