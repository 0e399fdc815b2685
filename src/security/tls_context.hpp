#pragma once

#include <openssl/types.h>

#include <memory>
#include <string>

#include "protocol/result.hpp"

// The TLS settings of Modbus/TCP Security ([SEC]), made once per server or client and shared by
// its sessions: TLS 1.2 or newer, mutual authentication against the lab's CA, and no
// renegotiation.
namespace mblab::security {

// What every command that speaks mbaps takes: --cert FILE --key FILE --ca FILE.
struct TlsFiles {
    std::string cert;  // this side's certificate (PEM; a chain may follow it)
    std::string key;   // its private key (PEM)
    std::string ca;    // the CA that must have signed the peer's certificate (PEM)

    bool empty() const { return cert.empty() && key.empty() && ca.empty(); }
};

struct ContextDeleter {
    void operator()(SSL_CTX* context) const;
};
using SharedContext = std::shared_ptr<SSL_CTX>;

// The versions a client offers. The security suite offers old versions on purpose, to see a
// server refuse them.
enum class ClientVersions : unsigned char {
    Modern,  // TLS 1.2 and 1.3, as the spec requires
    Tls12,   // TLS 1.2 only: renegotiation exists there
    Tls10,   // TLS 1.0 only
    Tls11,   // TLS 1.1 only
};

struct ClientSettings {
    ClientVersions versions = ClientVersions::Modern;
    // Checks the server's certificate against the CA and its name (SAN) against the host the
    // client connects to. The security suite turns this off to examine a server it does not trust.
    bool verify_server = true;
};

// The errors name the file and what is wrong with it, on one line.
protocol::Result<SharedContext, std::string> make_server_context(const TlsFiles& files);
// A client without files is allowed (cert and key empty): the suite connects that way to see the
// server refuse it; `ca` may be empty when verify_server is false.
protocol::Result<SharedContext, std::string> make_client_context(const TlsFiles& files,
                                                                 const ClientSettings& settings);

// The first error on OpenSSL's queue of this thread, as one line, and the queue cleared.
std::string take_openssl_error(const char* fallback);

// "--cert needs --key and --ca": what is missing from a set of files given, or "" when whole.
std::string incomplete_files(const TlsFiles& files);

}  // namespace mblab::security
