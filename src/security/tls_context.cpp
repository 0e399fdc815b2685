#include "security/tls_context.hpp"

#include <openssl/err.h>
#include <openssl/ssl.h>
#include <openssl/x509_vfy.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <fstream>

namespace mblab::security {

namespace {

// TLS 1.2 suites with forward secrecy and AEAD only; [SEC] requires the two AES-128-GCM ECDHE
// suites, the rest are what modern peers prefer. TLS 1.3 suites are OpenSSL's defaults.
constexpr const char* kTls12Ciphers =
    "ECDHE-ECDSA-AES128-GCM-SHA256:ECDHE-RSA-AES128-GCM-SHA256:"
    "ECDHE-ECDSA-AES256-GCM-SHA384:ECDHE-RSA-AES256-GCM-SHA384:"
    "ECDHE-ECDSA-CHACHA20-POLY1305:ECDHE-RSA-CHACHA20-POLY1305";
constexpr const char* kGroups = "P-256:X25519:P-384";
constexpr unsigned char kSessionContext[] = "mblab-mbaps";

// A readable file, or the reason it is not, before OpenSSL's less direct messages.
std::string check_readable(const char* option, const std::string& path) {
    if (path.empty()) return std::string(option) + " FILE is required";
    std::ifstream in(path);
    if (!in) return std::string(option) + " " + path + ": " + std::strerror(errno);
    return {};
}

bool load_own(SSL_CTX* context, const TlsFiles& files, std::string& error) {
    if (SSL_CTX_use_certificate_chain_file(context, files.cert.c_str()) != 1) {
        error = "--cert " + files.cert + ": " + take_openssl_error("not a PEM certificate");
        return false;
    }
    const bool loaded =
        SSL_CTX_use_PrivateKey_file(context, files.key.c_str(), SSL_FILETYPE_PEM) == 1;
    const auto reason = loaded ? std::string() : take_openssl_error("not a PEM private key");
    if (reason == "key values mismatch" || (loaded && SSL_CTX_check_private_key(context) != 1)) {
        ERR_clear_error();
        error = "--key " + files.key + " is not the key of --cert " + files.cert;
        return false;
    }
    if (!loaded) {
        error = "--key " + files.key + ": " + reason;
        return false;
    }
    return true;
}

bool load_ca(SSL_CTX* context, const TlsFiles& files, std::string& error) {
    if (SSL_CTX_load_verify_locations(context, files.ca.c_str(), nullptr) != 1) {
        error = "--ca " + files.ca + ": " + take_openssl_error("no PEM certificate in it");
        return false;
    }
    return true;
}

SharedContext new_context(const SSL_METHOD* method) {
    return SharedContext(SSL_CTX_new(method), ContextDeleter{});
}

}  // namespace

void ContextDeleter::operator()(SSL_CTX* context) const {
    SSL_CTX_free(context);
}

std::string take_openssl_error(const char* fallback) {
    const auto code = ERR_get_error();
    ERR_clear_error();
    if (code == 0) return fallback;
    std::array<char, 256> text{};
    // The reason alone ("no start line"), not OpenSSL's library:function:reason form.
    const char* reason = ERR_reason_error_string(code);
    if (reason) return reason;
    ERR_error_string_n(code, text.data(), text.size());
    return text.data();
}

std::string incomplete_files(const TlsFiles& files) {
    if (files.cert.empty()) return "--cert FILE is required";
    if (files.key.empty()) return "--key FILE is required";
    if (files.ca.empty()) return "--ca FILE is required";
    return {};
}

protocol::Result<SharedContext, std::string> make_server_context(const TlsFiles& files) {
    for (const auto& [option, path] :
         {std::pair{"--cert", &files.cert}, std::pair{"--key", &files.key},
          std::pair{"--ca", &files.ca}}) {
        if (auto error = check_readable(option, *path); !error.empty()) return error;
    }
    auto context = new_context(TLS_server_method());
    if (!context) return take_openssl_error("cannot make a TLS context");
    SSL_CTX* ctx = context.get();
    SSL_CTX_set_min_proto_version(ctx, TLS1_2_VERSION);
    // Renegotiation would let a client change its certificate, and so its role, in a session
    // whose role was read once; a refused renegotiation leaves the session as it was.
    SSL_CTX_set_options(ctx, SSL_OP_NO_RENEGOTIATION | SSL_OP_CIPHER_SERVER_PREFERENCE);
    SSL_CTX_set_cipher_list(ctx, kTls12Ciphers);
    SSL_CTX_set1_groups_list(ctx, kGroups);
    // The record buffers stay with a busy session (no SSL_MODE_RELEASE_BUFFERS): giving them back
    // whenever they are empty cost an allocation and a free of each per request and answer, 7 %
    // of the server's instructions over mbaps://. They are about 33 KB of heap per connection;
    // the server's driver gives them back when a session rests (server/mbap_driver).
    SSL_CTX_set_mode(ctx, SSL_MODE_ENABLE_PARTIAL_WRITE);
    std::string error;
    if (!load_own(ctx, files, error) || !load_ca(ctx, files, error)) return error;
    // The CertificateRequest names the CA, so a client holding several picks the right one.
    if (auto* names = SSL_load_client_CA_file(files.ca.c_str())) {
        SSL_CTX_set_client_CA_list(ctx, names);
    }
    ERR_clear_error();
    // TlsChannel adds the role check to each server session's verification.
    SSL_CTX_set_verify(ctx, SSL_VERIFY_PEER | SSL_VERIFY_FAIL_IF_NO_PEER_CERT, nullptr);
    // Resumed sessions keep the client's certificate, so the role read at the full handshake
    // stays the session's role.
    SSL_CTX_set_session_id_context(ctx, kSessionContext, sizeof kSessionContext - 1);
    SSL_CTX_set_session_cache_mode(ctx, SSL_SESS_CACHE_SERVER);
    return context;
}

protocol::Result<SharedContext, std::string> make_client_context(const TlsFiles& files,
                                                                 const ClientSettings& settings) {
    if (!files.cert.empty() || !files.key.empty()) {
        for (const auto& [option, path] :
             {std::pair{"--cert", &files.cert}, std::pair{"--key", &files.key}}) {
            if (auto error = check_readable(option, *path); !error.empty()) return error;
        }
    }
    if (settings.verify_server) {
        if (auto error = check_readable("--ca", files.ca); !error.empty()) return error;
    }
    auto context = new_context(TLS_client_method());
    if (!context) return take_openssl_error("cannot make a TLS context");
    SSL_CTX* ctx = context.get();
    switch (settings.versions) {
        case ClientVersions::Modern:
        case ClientVersions::Tls12:
            SSL_CTX_set_min_proto_version(ctx, TLS1_2_VERSION);
            if (settings.versions == ClientVersions::Tls12) {
                SSL_CTX_set_max_proto_version(ctx, TLS1_2_VERSION);
            }
            SSL_CTX_set_cipher_list(ctx, kTls12Ciphers);
            SSL_CTX_set1_groups_list(ctx, kGroups);
            break;
        case ClientVersions::Tls10:
        case ClientVersions::Tls11: {
            const int version =
                settings.versions == ClientVersions::Tls10 ? TLS1_VERSION : TLS1_1_VERSION;
            SSL_CTX_set_min_proto_version(ctx, version);
            SSL_CTX_set_max_proto_version(ctx, version);
            // OpenSSL 3 will not offer these versions at its default security level.
            SSL_CTX_set_cipher_list(ctx, "DEFAULT:@SECLEVEL=0");
            break;
        }
    }
    SSL_CTX_set_mode(ctx, SSL_MODE_ENABLE_PARTIAL_WRITE);
    std::string error;
    if (!files.cert.empty() && !load_own(ctx, files, error)) return error;
    if (!files.ca.empty() && !load_ca(ctx, files, error)) return error;
    SSL_CTX_set_verify(ctx, settings.verify_server ? SSL_VERIFY_PEER : SSL_VERIFY_NONE, nullptr);
    SSL_CTX_set_session_cache_mode(ctx, SSL_SESS_CACHE_CLIENT);
    return context;
}

}  // namespace mblab::security
