// A client and a server TlsChannel driven into each other through memory, without a socket: the
// handshake, the role the server reads, plaintext both ways, the refusals and their reasons.
#include <gtest/gtest.h>
#include <malloc.h>

#include <filesystem>
#include <string>
#include <vector>

#include "security/pki.hpp"
#include "security/tls_channel.hpp"
#include "security/tls_context.hpp"

namespace mblab::test {
namespace {

namespace fs = std::filesystem;
using security::ClientSettings;
using security::ClientVersions;
using security::RoleReading;
using security::TlsChannel;
using State = TlsChannel::State;

// One lab PKI for the whole suite: making keys is the slow part.
class LabPki {
  public:
    static const fs::path& dir() {
        static const LabPki pki;
        return pki.dir_;
    }

  private:
    LabPki() {
        dir_ = fs::temp_directory_path() / ("mblab-tls-channel-" + std::to_string(::getpid()));
        fs::remove_all(dir_);
        auto made = security::make_lab_pki(dir_, {});
        if (!made) throw std::runtime_error(made.error());
    }
    ~LabPki() { fs::remove_all(dir_); }
    fs::path dir_;
};

security::TlsFiles files(const std::string& name) {
    const auto dir = LabPki::dir();
    return {(dir / (name + ".pem")).string(), (dir / (name + ".key")).string(),
            (dir / "ca.pem").string()};
}

security::SharedContext server_context() {
    auto context = security::make_server_context(files("server"));
    EXPECT_TRUE(context) << (context ? "" : context.error());
    return context ? *context : nullptr;
}

security::SharedContext client_context(const std::string& name, ClientSettings settings = {}) {
    auto f = name.empty() ? security::TlsFiles{"", "", files("server").ca} : files(name);
    auto context = security::make_client_context(f, settings);
    EXPECT_TRUE(context) << (context ? "" : context.error());
    return context ? *context : nullptr;
}

// Moves what each side has for the network to the other until neither has anything.
void exchange(TlsChannel& client, TlsChannel& server) {
    for (int round = 0; round < 20; ++round) {
        bool moved = false;
        for (auto [from, to] : {std::pair{&client, &server}, std::pair{&server, &client}}) {
            const auto out = from->output();
            if (out.empty()) continue;
            moved = true;
            to->received(out);
            from->sent(out.size());
            // Moves a handshake on; records after it wait for read_all().
            if (to->state() == State::Handshaking) to->read({});
        }
        if (!moved) return;
    }
}

std::string read_all(TlsChannel& channel) {
    std::string text;
    std::vector<std::uint8_t> buffer(7);  // small, so a record is taken in several reads
    while (std::size_t n = channel.read(buffer))
        text.append(buffer.begin(), buffer.begin() + n);
    return text;
}

void write(TlsChannel& channel, std::string_view text) {
    ASSERT_TRUE(channel.write({reinterpret_cast<const std::uint8_t*>(text.data()), text.size()}));
}

struct Pair {
    explicit Pair(const std::string& client_name, ClientSettings settings = {})
        : server(server_context(), TlsChannel::Side::Server),
          client(client_context(client_name, settings), TlsChannel::Side::Client, "localhost") {
        client.start();
        exchange(client, server);
    }
    TlsChannel server;
    TlsChannel client;
};

TEST(TlsChannel, MutualHandshakeReadsTheClientsRoleOnce) {
    Pair p("client-Operator");
    ASSERT_EQ(p.server.state(), State::Open) << p.server.error();
    ASSERT_EQ(p.client.state(), State::Open) << p.client.error();
    EXPECT_EQ(p.server.peer().role.kind, RoleReading::Kind::Role);
    EXPECT_EQ(p.server.peer().role.role, "Operator");
    EXPECT_EQ(p.client.peer().own_role.role, "Operator");
    EXPECT_EQ(p.server.peer().version, "TLSv1.3");
    EXPECT_NE(p.client.peer().subject.find("server"), std::string::npos) << p.client.peer().subject;
}

TEST(TlsChannel, CarriesBytesBothWaysUnchanged) {
    Pair p("client-ReadOnly");
    ASSERT_EQ(p.server.state(), State::Open);
    const std::string request("\x00\x01\x00\x00\x00\x06\x01\x03\x00\x00\x00\x01", 12);
    write(p.client, request);
    exchange(p.client, p.server);
    EXPECT_EQ(read_all(p.server), request);
    const std::string answer("\x00\x01\x00\x00\x00\x05\x01\x03\x02\x12\x34", 11);
    write(p.server, answer);
    exchange(p.client, p.server);
    EXPECT_EQ(read_all(p.client), answer);
}

// The socket takes part of what the channel has for it, and the peer's bytes come a few at a time:
// every record is still read whole, once, in order.
TEST(TlsChannel, RecordsLeavingInPartsAndArrivingInPiecesAreReadWhole) {
    Pair p("client-ReadOnly");
    ASSERT_EQ(p.server.state(), State::Open);
    std::string sent_text;
    for (int i = 0; i < 3; ++i) {
        const std::string request = "request " + std::to_string(i) + std::string(40 + i, 'x');
        write(p.client, request);
        sent_text += request;
    }
    std::string got;
    std::vector<std::uint8_t> plain(64);
    while (!p.client.output().empty()) {
        const auto out = p.client.output();
        const std::size_t part = std::min<std::size_t>(out.size(), 5);
        p.server.received(out.first(part));
        p.client.sent(part);  // the rest stays for the next send, its first byte first
        while (std::size_t n = p.server.read(plain))
            got.append(plain.begin(), plain.begin() + n);
    }
    EXPECT_EQ(got, sent_text);
    EXPECT_FALSE(p.server.has_input());
    EXPECT_EQ(p.server.state(), State::Open) << p.server.error();
}

// Heap in use, for the release test; the sanitizers' allocator does not keep glibc's count
// (g++ says so with __SANITIZE_ADDRESS__, clang 14 only through __has_feature).
#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define MBLAB_TEST_ASAN 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__) || defined(MBLAB_TEST_ASAN)
constexpr bool kHeapCounted = false;
#else
constexpr bool kHeapCounted = true;
#endif

std::size_t heap_in_use() {
    return mallinfo2().uordblks;
}

TEST(TlsChannel, AChannelAtRestGivesItsRecordBuffersBackAndCarriesRecordsAfter) {
    Pair p("client-ReadOnly");
    ASSERT_EQ(p.server.state(), State::Open);
    write(p.client, "request 1");
    exchange(p.client, p.server);
    EXPECT_EQ(read_all(p.server), "request 1");
    EXPECT_FALSE(p.server.resting());
    const auto before = heap_in_use();
    ASSERT_TRUE(p.server.release_buffers());
    EXPECT_TRUE(p.server.resting());
    // OpenSSL's read and write buffers are about 16.7 KB each.
    if (kHeapCounted) {
        EXPECT_GE(before - heap_in_use(), 30'000U) << before - heap_in_use();
    }
    write(p.client, "request 2");
    exchange(p.client, p.server);
    EXPECT_FALSE(p.server.resting());
    EXPECT_EQ(read_all(p.server), "request 2");
    write(p.server, "answer 2");
    exchange(p.client, p.server);
    EXPECT_EQ(read_all(p.client), "answer 2");
    EXPECT_EQ(p.server.state(), State::Open) << p.server.error();
}

// A record that came in part, or came and was not read, is in the buffers: they stay, and the
// record is read whole once the rest comes.
TEST(TlsChannel, ARecordOnItsWayKeepsTheBuffers) {
    Pair p("client-ReadOnly");
    ASSERT_EQ(p.server.state(), State::Open);
    write(p.client, "request 1");
    p.server.received(p.client.output().first(10));
    p.client.sent(10);
    EXPECT_EQ(read_all(p.server), "");
    EXPECT_FALSE(p.server.release_buffers());
    EXPECT_FALSE(p.server.resting());
    exchange(p.client, p.server);
    EXPECT_FALSE(p.server.release_buffers()) << "a record received, not read";
    EXPECT_EQ(read_all(p.server), "request 1");
    write(p.server, "answer 1");
    EXPECT_FALSE(p.server.release_buffers()) << "a record not yet sent";
    exchange(p.client, p.server);
    EXPECT_TRUE(p.server.release_buffers());
    EXPECT_EQ(read_all(p.client), "answer 1");
}

// Plaintext decrypted and not yet read lives in the read buffer: no rest until it is read.
TEST(TlsChannel, UnreadPlaintextKeepsTheBuffers) {
    Pair p("client-ReadOnly");
    ASSERT_EQ(p.server.state(), State::Open);
    write(p.client, "a request longer than one read");
    exchange(p.client, p.server);
    std::vector<std::uint8_t> first(7);
    ASSERT_EQ(p.server.read(first), 7U);
    EXPECT_FALSE(p.server.release_buffers());
    EXPECT_EQ(std::string(first.begin(), first.end()) + read_all(p.server),
              "a request longer than one read");
    EXPECT_TRUE(p.server.release_buffers());
}

TEST(TlsChannel, AHandshakingChannelDoesNotRest) {
    TlsChannel server(server_context(), TlsChannel::Side::Server);
    EXPECT_FALSE(server.release_buffers());
}

TEST(TlsChannel, TlsTwelveOnlyClientGetsTlsTwelve) {
    Pair p("client-Operator", {ClientVersions::Tls12, true});
    ASSERT_EQ(p.server.state(), State::Open) << p.server.error();
    EXPECT_EQ(p.server.peer().version, "TLSv1.2");
    EXPECT_EQ(p.server.peer().role.role, "Operator");
}

TEST(TlsChannel, CertificateWithoutRoleHasTheNullRole) {
    Pair p("client-norole");
    ASSERT_EQ(p.server.state(), State::Open) << p.server.error();
    EXPECT_EQ(p.server.peer().role.kind, RoleReading::Kind::None);
}

struct Refusal {
    const char* client;
    const char* reason;  // part of the server's error
};

class TlsRefusal : public ::testing::TestWithParam<Refusal> {};

TEST_P(TlsRefusal, ServerFailsTheHandshakeAndSaysWhy) {
    // TLS 1.2, where the client learns of the refusal within the handshake too.
    Pair p(GetParam().client, {ClientVersions::Tls12, true});
    EXPECT_EQ(p.server.state(), State::Failed);
    EXPECT_NE(p.server.error().find(GetParam().reason), std::string::npos) << p.server.error();
    EXPECT_EQ(p.client.state(), State::Failed);
}

INSTANTIATE_TEST_SUITE_P(Certificates, TlsRefusal,
                         ::testing::Values(Refusal{"client-expired", "certificate has expired"},
                                           Refusal{"client-foreign-ca",
                                                   "unable to get local issuer certificate"},
                                           Refusal{"client-self-signed", "self-signed certificate"},
                                           Refusal{"client-ia5-role", "IA5String"},
                                           Refusal{"client-two-roles", "more than one role"},
                                           Refusal{"", "peer did not return a certificate"}));

TEST(TlsChannel, RefusedCertificateUnderTlsThirteenFailsTheClientAtItsFirstRead) {
    Pair p("client-expired");
    EXPECT_EQ(p.server.state(), State::Failed);
    EXPECT_EQ(read_all(p.client), "");
    // The client finished its side of a TLS 1.3 handshake before the server judged it; the
    // server's alert ends it.
    EXPECT_EQ(p.client.state(), State::Failed);
    EXPECT_NE(p.client.error().find("certificate expired"), std::string::npos) << p.client.error();
}

TEST(TlsChannel, OldVersionsAreRefused) {
    for (auto versions : {ClientVersions::Tls10, ClientVersions::Tls11}) {
        Pair p("client-Operator", {versions, true});
        EXPECT_EQ(p.server.state(), State::Failed);
        EXPECT_NE(p.server.error().find("unsupported protocol"), std::string::npos)
            << p.server.error();
        // The client keeps the alert the server sent, which is how the tester tells a refusal
        // by the device from a failure of its own; the server read none.
        EXPECT_TRUE(p.client.alert_received().fatal);
        EXPECT_EQ(p.client.alert_received().description, 70);  // protocol_version
        EXPECT_EQ(p.client.alert_received().text, "fatal protocol version");
        EXPECT_FALSE(p.server.alert_received().received);
    }
}

TEST(TlsChannel, Tls12SessionsCarryTheRenegotiationIndication) {
    Pair p("client-Operator", {ClientVersions::Tls12, true});
    ASSERT_EQ(p.client.state(), State::Open);
    EXPECT_EQ(p.client.peer().version, "TLSv1.2");
    EXPECT_TRUE(p.client.secure_renegotiation());
    EXPECT_TRUE(p.server.secure_renegotiation());
}

TEST(TlsChannel, ServerNameMustBeInTheServersCertificate) {
    TlsChannel server(server_context(), TlsChannel::Side::Server);
    TlsChannel client(client_context("client-Operator"), TlsChannel::Side::Client, "example.org");
    client.start();
    exchange(client, server);
    EXPECT_EQ(client.state(), State::Failed);
    EXPECT_NE(client.error().find("hostname mismatch"), std::string::npos) << client.error();
}

// TLS 1.2 (RFC 5246 7.2.1): the server answers the client's close_notify at once.
TEST(TlsChannel, OverTls12CloseNotifyIsAnsweredAtOnce) {
    Pair p("client-Operator", {ClientVersions::Tls12, true});
    ASSERT_EQ(p.server.state(), State::Open);
    p.client.close();
    exchange(p.client, p.server);
    EXPECT_EQ(read_all(p.server), "");
    EXPECT_EQ(p.server.state(), State::Closed);
    const std::string late = "too late";
    EXPECT_FALSE(p.server.write({reinterpret_cast<const std::uint8_t*>(late.data()), late.size()}));
    exchange(p.client, p.server);
    EXPECT_EQ(read_all(p.client), "");
    EXPECT_EQ(p.client.state(), State::Closed);
}

// TLS 1.3 closes each direction on its own (RFC 8446 6.1): after the client's close_notify the
// server still writes what it owes, and its own close_notify ends the session.
TEST(TlsChannel, OverTls13TheServerWritesWhatItOwesAfterTheClientsCloseNotify) {
    Pair p("client-Operator");
    ASSERT_EQ(p.server.peer().version, "TLSv1.3");
    p.client.close();
    exchange(p.client, p.server);
    EXPECT_EQ(read_all(p.server), "");
    EXPECT_TRUE(p.server.input_ended());
    EXPECT_EQ(p.server.state(), State::Open);
    EXPECT_FALSE(p.server.has_input());
    write(p.server, "owed answer");
    p.server.close();
    EXPECT_EQ(p.server.state(), State::Closed);
    exchange(p.client, p.server);
    EXPECT_EQ(read_all(p.client), "owed answer");
    EXPECT_EQ(p.client.state(), State::Closed);
}

TEST(TlsChannel, RenegotiationIsRefusedAndTheSessionGoesOn) {
    Pair p("client-Operator", {ClientVersions::Tls12, true});
    ASSERT_EQ(p.server.state(), State::Open);
    ASSERT_TRUE(p.client.request_renegotiation());
    exchange(p.client, p.server);
    EXPECT_EQ(p.server.state(), State::Open) << p.server.error();
    write(p.server, "still here");
    exchange(p.client, p.server);
    EXPECT_EQ(read_all(p.client), "still here");
}

TEST(TlsChannel, ResumedSessionKeepsTheRole) {
    const auto server_ctx = server_context();
    const auto client_ctx = client_context("client-Operator");
    SSL_SESSION* saved = nullptr;
    {
        TlsChannel server(server_ctx, TlsChannel::Side::Server);
        TlsChannel client(client_ctx, TlsChannel::Side::Client, "localhost");
        client.start();
        exchange(client, server);
        ASSERT_EQ(server.state(), State::Open);
        // The server sends its session tickets once it reads after the handshake, as a server
        // session does; the client takes them with its next read.
        read_all(server);
        exchange(client, server);
        read_all(client);
        saved = client.take_session();
        // OpenSSL forgets the session of a connection that ends without close_notify.
        client.close();
    }
    ASSERT_NE(saved, nullptr);
    TlsChannel server(server_ctx, TlsChannel::Side::Server);
    TlsChannel client(client_ctx, TlsChannel::Side::Client, "localhost");
    client.offer_session(saved);
    SSL_SESSION_free(saved);
    client.start();
    exchange(client, server);
    ASSERT_EQ(server.state(), State::Open) << server.error();
    EXPECT_TRUE(client.peer().resumed);
    EXPECT_TRUE(server.peer().resumed);
    EXPECT_EQ(server.peer().role.role, "Operator");
}

TEST(TlsContext, FileProblemsAreOneLineNamingTheFile) {
    auto missing = security::make_server_context({"/nonexistent/s.pem", "k", "c"});
    ASSERT_FALSE(missing);
    EXPECT_EQ(missing.error(), "--cert /nonexistent/s.pem: No such file or directory");
    auto mismatched = files("server");
    mismatched.key = files("client-Operator").key;
    auto wrong = security::make_server_context(mismatched);
    ASSERT_FALSE(wrong);
    EXPECT_NE(wrong.error().find("is not the key of --cert"), std::string::npos) << wrong.error();
    auto not_pem = files("server");
    not_pem.ca = "/etc/hostname";
    auto bad = security::make_server_context(not_pem);
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.error().find("--ca /etc/hostname"), std::string::npos) << bad.error();
}

}  // namespace
}  // namespace mblab::test
