#include "security/tls_channel.hpp"

#include <openssl/bio.h>
#include <openssl/err.h>
#include <openssl/ssl.h>
#include <openssl/x509.h>
#include <openssl/x509v3.h>

#include <array>

#include "support/name_table.hpp"

namespace mblab::security {

namespace {

// SSL_get_error() reads the thread's error queue, which must be empty before each call into
// TLS. Clearing a queue that is already empty walks all its slots; on every record that was a
// few per cent of the server's time.
void clear_error_queue() {
    if (ERR_peek_error() != 0) ERR_clear_error();
}

std::string subject_of(const X509* certificate) {
    if (!certificate) return {};
    std::array<char, 256> text{};
    X509_NAME_oneline(X509_get_subject_name(certificate), text.data(),
                      static_cast<int>(text.size()));
    return text.data();
}

// The client's role is part of authenticating it: a certificate whose role extension cannot be
// read as one role fails the handshake, like a certificate from an unknown CA.
int verify_client(int preverified, X509_STORE_CTX* store) {
    if (!preverified || X509_STORE_CTX_get_error_depth(store) != 0) return preverified;
    auto reading = read_role(X509_STORE_CTX_get_current_cert(store));
    if (reading.kind != RoleReading::Kind::Refused) return 1;
    const auto* ssl = static_cast<const SSL*>(
        X509_STORE_CTX_get_ex_data(store, SSL_get_ex_data_X509_STORE_CTX_idx()));
    if (auto* refusal = ssl ? static_cast<std::string*>(SSL_get_app_data(ssl)) : nullptr) {
        *refusal = std::move(reading.reason);
    }
    X509_STORE_CTX_set_error(store, X509_V_ERR_APPLICATION_VERIFICATION);
    return 0;
}

bool is_ip_address(std::string_view host) {
    return host.find(':') != std::string_view::npos ||
           host.find_first_not_of("0123456789.") == std::string_view::npos;
}

// Where each SSL keeps its channel, for the alert callback.
int channel_index() {
    static const int index = SSL_get_ex_new_index(0, nullptr, nullptr, nullptr, nullptr);
    return index;
}

}  // namespace

void note_alert(const SSL* ssl, int where, int value) {
    // SSL_CB_READ_ALERT is two bits (alert, read): an alert this side writes has one of them.
    if ((where & SSL_CB_READ_ALERT) != SSL_CB_READ_ALERT) return;
    auto* channel = static_cast<TlsChannel*>(SSL_get_ex_data(ssl, channel_index()));
    if (channel == nullptr) return;
    TlsAlert& alert = channel->alert_;
    alert.received = true;
    alert.fatal = (value >> 8) == SSL3_AL_FATAL;
    alert.description = value & 0xFF;
    std::string description = SSL_alert_desc_string_long(value);
    // OpenSSL 3.0 names no alert that TLS 1.3 added; the one a device sends most is 116.
    if (description == "unknown") {
        description = alert.description == 116 ? "certificate required"
                                               : "alert " + std::to_string(alert.description);
    }
    alert.text = std::string(SSL_alert_type_string_long(value)) + " " + description;
}

TlsChannel::TlsChannel(const SharedContext& context, Side side, std::string_view server_name)
    : side_(side) {
    ssl_ = SSL_new(context.get());
    BIO* in = new_queue_bio(input_);
    BIO* out = new_queue_bio(output_);
    if (!ssl_ || !in || !out) {
        BIO_free(in);
        BIO_free(out);
        fail("out of memory for a TLS session");
        return;
    }
    SSL_set_bio(ssl_, in, out);
    SSL_set_ex_data(ssl_, channel_index(), this);
    SSL_set_info_callback(ssl_, note_alert);
    if (side == Side::Server) {
        SSL_set_accept_state(ssl_);
        SSL_set_app_data(ssl_, &role_refusal_);
        SSL_set_verify(ssl_, SSL_get_verify_mode(ssl_), verify_client);
        return;
    }
    SSL_set_connect_state(ssl_);
    if (server_name.empty()) return;
    const std::string host(server_name);
    if (is_ip_address(host)) {
        X509_VERIFY_PARAM_set1_ip_asc(SSL_get0_param(ssl_), host.c_str());
    } else {
        SSL_set_tlsext_host_name(ssl_, host.c_str());
        SSL_set1_host(ssl_, host.c_str());
    }
}

TlsChannel::~TlsChannel() {
    SSL_free(ssl_);  // frees both BIOs
}

void TlsChannel::start() {
    if (state_ == State::Handshaking) handshake();
}

void TlsChannel::received(std::span<const std::uint8_t> bytes) {
    resting_ = false;
    if (ssl_) input_.append(bytes);
}

bool TlsChannel::release_buffers() {
    if (state_ != State::Open || !input_.empty() || !output_.empty()) return false;
    // Plaintext not yet handed out points into the read buffer: OpenSSL before 3.0.14
    // (CVE-2024-4741) freed it anyway. It refuses on its own while part of a record is there.
    if (SSL_pending(ssl_) > 0 || SSL_free_buffers(ssl_) != 1) return false;
    input_.release();
    output_.release();
    resting_ = true;
    return true;
}

void TlsChannel::handshake() {
    ERR_clear_error();
    const int result = SSL_do_handshake(ssl_);
    if (result == 1) {
        finish_handshake();
        return;
    }
    switch (SSL_get_error(ssl_, result)) {
        case SSL_ERROR_WANT_READ:
        case SSL_ERROR_WANT_WRITE:
            return;
        default:
            fail("the TLS handshake failed");
    }
}

void TlsChannel::finish_handshake() {
    state_ = State::Open;
    peer_.version = SSL_get_version(ssl_);
    peer_.cipher = SSL_get_cipher_name(ssl_);
    peer_.resumed = SSL_session_reused(ssl_) == 1;
    const X509* certificate = SSL_get0_peer_certificate(ssl_);
    peer_.subject = subject_of(certificate);
    if (certificate) peer_.role = read_role(certificate);
    if (const X509* own = SSL_get_certificate(ssl_)) peer_.own_role = read_role(own);
}

std::string TlsChannel::verify_failure() const {
    const long result = SSL_get_verify_result(ssl_);
    if (result == X509_V_OK) return {};
    const char* whose = side_ == Side::Server ? "the client's" : "the server's";
    if (result == X509_V_ERR_APPLICATION_VERIFICATION && !role_refusal_.empty()) {
        return std::string(whose) + " certificate was refused: " + role_refusal_;
    }
    return std::string(whose) +
           " certificate was refused: " + X509_verify_cert_error_string(result);
}

void TlsChannel::fail(const char* fallback) {
    state_ = State::Failed;
    const auto verify = ssl_ ? verify_failure() : std::string();
    const auto detail = take_openssl_error(fallback);
    error_ = verify.empty() ? detail : verify;
}

std::size_t TlsChannel::read(std::span<std::uint8_t> out) {
    if (state_ == State::Handshaking) handshake();
    if (state_ != State::Open || input_ended_ || out.empty()) return 0;
    clear_error_queue();
    std::size_t got = 0;
    const int result = SSL_read_ex(ssl_, out.data(), out.size(), &got);
    if (result == 1) return got;
    switch (SSL_get_error(ssl_, result)) {
        case SSL_ERROR_WANT_READ:
        case SSL_ERROR_WANT_WRITE:
            break;
        case SSL_ERROR_ZERO_RETURN:
            ERR_clear_error();
            // TLS 1.3 closes each direction on its own (RFC 8446 6.1): a server still sends the
            // answers it owes (a gateway's, a delayed one), then its close_notify. TLS 1.2 asks
            // for ours at once, pending writes discarded (RFC 5246 7.2.1), and a client gets
            // nothing more to wait for than the end.
            if (side_ == Side::Server && SSL_version(ssl_) >= TLS1_3_VERSION) {
                input_ended_ = true;
                break;
            }
            state_ = State::Closed;
            SSL_shutdown(ssl_);
            ERR_clear_error();
            break;
        default:
            fail("a TLS record could not be read");
    }
    return 0;
}

bool TlsChannel::has_input() const {
    return ssl_ && !input_ended_ && (!input_.empty() || SSL_pending(ssl_) > 0);
}

bool TlsChannel::write(std::span<const std::uint8_t> plain) {
    if (state_ != State::Open) return false;
    resting_ = false;
    clear_error_queue();
    while (!plain.empty()) {
        std::size_t written = 0;
        if (SSL_write_ex(ssl_, plain.data(), plain.size(), &written) != 1) {
            fail("a TLS record could not be written");
            return false;
        }
        plain = plain.subspan(written);
    }
    return true;
}

void TlsChannel::close() {
    if (state_ != State::Open) return;
    ERR_clear_error();
    SSL_shutdown(ssl_);
    ERR_clear_error();
    // Both sides have now said close_notify.
    if (input_ended_) state_ = State::Closed;
}

void TlsChannel::offer_session(SSL_SESSION* session) {
    if (session) SSL_set_session(ssl_, session);
}

SSL_SESSION* TlsChannel::take_session() const {
    return ssl_ ? SSL_get1_session(ssl_) : nullptr;
}

bool TlsChannel::request_renegotiation() {
    if (state_ != State::Open) return false;
    ERR_clear_error();
    // TLS 1.3 has no renegotiation; its nearest is a key update, which a server must accept.
    const int result = SSL_version(ssl_) >= TLS1_3_VERSION
                           ? SSL_key_update(ssl_, SSL_KEY_UPDATE_REQUESTED)
                           : SSL_renegotiate(ssl_);
    if (result != 1) {
        ERR_clear_error();
        return false;
    }
    ERR_clear_error();
    SSL_do_handshake(ssl_);
    ERR_clear_error();
    return true;
}

bool TlsChannel::secure_renegotiation() const {
    if (!ssl_ || state_ == State::Handshaking) return false;
    return SSL_version(ssl_) >= TLS1_3_VERSION || SSL_get_secure_renegotiation_support(ssl_) == 1;
}

std::string_view state_name(TlsChannel::State state) {
    static constexpr Named<TlsChannel::State> kNames[] = {
        {TlsChannel::State::Handshaking, "handshaking"},
        {TlsChannel::State::Open, "open"},
        {TlsChannel::State::Closed, "closed"},
        {TlsChannel::State::Failed, "failed"}};
    return name_of(kNames, state, "unknown");
}

}  // namespace mblab::security
