// TLS over a memory pair, both sides transport::TlsStream: the handshake through short writes
// and a stalled reader, a peer that resets or closes in the middle of it, a refused name,
// gathered writes as one record, close_notify read as the end of input, and what a read says of
// the ciphertext it left below.
#include <gtest/gtest.h>

#include <array>
#include <cerrno>
#include <string>

#include "support/lab_tls.hpp"
#include "transport/memory_channel.hpp"
#include "transport/tls_stream.hpp"

namespace mblab::test {
namespace {

using transport::Io;
using transport::MemoryPair;
using transport::TlsStream;
using Status = Io::Status;
using TlsState = security::TlsChannel::State;

struct TlsPair {
    explicit TlsPair(const std::string& server_name = "localhost")
        : client(pair.client(), lab_client_context("client-Operator"), TlsStream::Side::Client,
                 server_name),
          server(pair.server(), lab_server_context(), TlsStream::Side::Server) {
        client.start();
    }

    // Both sides take turns until neither is in its handshake; false if that never happens.
    bool handshake(int rounds = 200) {
        for (int round = 0; round < rounds; ++round) {
            if (!client.handshaking() && !server.handshaking()) return true;
            if (client.handshaking()) last_client = client.handshake();
            if (server.handshaking()) last_server = server.handshake();
        }
        return !client.handshaking() && !server.handshaking();
    }

    MemoryPair pair;
    TlsStream client;
    TlsStream server;
    Io last_client;
    Io last_server;
};

std::span<const std::uint8_t> bytes_of(const std::string& text) {
    return {reinterpret_cast<const std::uint8_t*>(text.data()), text.size()};
}

std::string read_text(TlsStream& stream, Status* status = nullptr) {
    std::array<std::uint8_t, 256> buffer{};
    const auto io = stream.read(buffer);
    if (status != nullptr) *status = io.status;
    return io.status == Status::Done ? std::string(buffer.begin(), buffer.begin() + io.bytes) : "";
}

TEST(TlsStream, HandshakeGoesThroughShortWritesBothWays) {
    TlsPair p;
    p.pair.client().set_max_write(7);
    p.pair.server().set_max_write(7);
    ASSERT_TRUE(p.handshake());
    ASSERT_EQ(p.client.session().state(), TlsState::Open) << p.client.error();
    ASSERT_EQ(p.server.session().state(), TlsState::Open) << p.server.error();
    const auto peer = p.server.peer();
    ASSERT_NE(peer.tls, nullptr);
    EXPECT_EQ(peer.tls->role.role, "Operator");
    EXPECT_EQ(peer.address_size, 0U);  // a memory pair has no address

    EXPECT_EQ(p.client.write(bytes_of("request")).bytes, 7U);
    std::string got;
    for (int i = 0; i < 50 && got.size() < 7; ++i) {
        got += read_text(p.server);
        p.client.flush();  // the rest of the record, 7 bytes at a time
    }
    EXPECT_EQ(got, "request");
}

TEST(TlsStream, StalledPeerHoldsTheHandshakeUntilItReadsAgain) {
    TlsPair p;
    p.pair.server().set_window(0);  // the client reads nothing the server sends
    EXPECT_FALSE(p.handshake(50));
    EXPECT_EQ(p.last_client.status, Status::WouldBlock);
    EXPECT_TRUE(p.server.wants_write()) << "the server's flight waits for room";
    p.pair.server().set_window(1 << 20);
    ASSERT_TRUE(p.handshake());
    EXPECT_EQ(p.client.session().state(), TlsState::Open) << p.client.error();
}

TEST(TlsStream, PeerResetInTheHandshakeIsAClearFailureNotAWait) {
    TlsPair p;
    p.server.handshake();  // took the hello, sent its flight
    p.pair.server().reset();
    const auto io = p.client.handshake();
    EXPECT_EQ(io.status, Status::Failed);
    EXPECT_EQ(io.code, ECONNRESET);
    EXPECT_TRUE(p.client.heard_peer());
    EXPECT_FALSE(p.client.session().state() == TlsState::Open);
}

TEST(TlsStream, PeerThatClosesInTheHandshakeEndsIt) {
    TlsPair p;
    // It takes the ClientHello first: closed with it unread, the pair resets as a socket does.
    std::array<std::uint8_t, 4096> hello{};
    ASSERT_EQ(p.pair.server().read(hello).status, Status::Done);
    p.pair.server().close();
    const auto io = p.client.handshake();
    EXPECT_EQ(io.status, Status::EndOfInput);
    EXPECT_EQ(p.client.error(), "the peer closed the connection during the TLS handshake");
}

TEST(TlsStream, RefusedServerNameFailsWithTheReasonAndTellsThePeer) {
    TlsPair p("example.org");
    EXPECT_TRUE(p.handshake());
    EXPECT_EQ(p.last_client.status, Status::Failed);
    EXPECT_EQ(p.last_client.code, 0) << "a TLS failure, not a socket's";
    EXPECT_NE(p.client.error().find("hostname mismatch"), std::string::npos) << p.client.error();
    // The alert went out: the server reads its failure rather than waiting for more.
    Status status = Status::Done;
    read_text(p.server, &status);
    EXPECT_EQ(status, Status::Failed);
}

TEST(TlsStream, GatheredBuffersGoOutAsOneRecord) {
    TlsPair p;
    ASSERT_TRUE(p.handshake());
    read_text(p.server);  // a TLS 1.3 server sends its tickets once it reads
    read_text(p.client);
    const std::string a = "first answer";
    const std::string b = "second one..";
    const std::string c = "third one...";
    const std::array<iovec, 3> gathered{iovec{const_cast<char*>(a.data()), a.size()},
                                        iovec{const_cast<char*>(b.data()), b.size()},
                                        iovec{const_cast<char*>(c.data()), c.size()}};
    const auto before = p.pair.server().written();
    EXPECT_EQ(p.server.writev(gathered).bytes, 36U);
    // TLS 1.3: a 5-byte header, the 36 bytes, the content type, a 16-byte tag.
    EXPECT_EQ(p.pair.server().written() - before, 5U + 36U + 1U + 16U);
    EXPECT_EQ(read_text(p.client), a + b + c);
}

TEST(TlsStream, WriteWaitsWhileTheRecordsBeforeItAreHeldBack) {
    TlsPair p;
    ASSERT_TRUE(p.handshake());
    p.pair.client().set_window(10);
    EXPECT_EQ(p.client.write(bytes_of(std::string(100, 'x'))).bytes, 100U);
    EXPECT_TRUE(p.client.wants_write());
    EXPECT_EQ(p.client.write(bytes_of("more")).status, Status::WouldBlock);
    std::string got;
    for (int i = 0; i < 100 && got.size() < 100; ++i) {
        got += read_text(p.server);
        p.client.flush();
    }
    EXPECT_EQ(got, std::string(100, 'x'));
    EXPECT_FALSE(p.client.wants_write());
}

// A read takes at most a record's worth of ciphertext from below; while more waits there, an owner
// woken only by new input must be told to read again.
TEST(TlsStream, InputMayRemainWhileTheChannelBelowHoldsCiphertext) {
    TlsPair p;
    ASSERT_TRUE(p.handshake());
    const std::string plain(3 * TlsStream::kPlainBatch, 'r');  // three full records
    ASSERT_EQ(p.client.write(bytes_of(plain)).status, Status::Done);
    ASSERT_GT(p.pair.server().pending(), TlsStream::kCipherChunk);

    EXPECT_EQ(read_text(p.server).size(), 256U);
    EXPECT_TRUE(p.server.input_may_remain()) << "two records still below";

    std::size_t total = 256;
    for (Status status = Status::Done; status == Status::Done;) {
        total += read_text(p.server, &status).size();
    }
    EXPECT_EQ(total, plain.size());
    EXPECT_EQ(p.pair.server().pending(), 0U);
    EXPECT_FALSE(p.server.input_may_remain()) << "the last read below took what was there";
}

// Over TLS 1.3 the server's side stays open for what it owes until it shuts it down itself.
TEST(TlsStream, CloseNotifyIsReadAsTheEndOfInput) {
    TlsPair p;
    ASSERT_TRUE(p.handshake());
    p.client.shutdown_write();
    Status status = Status::Done;
    read_text(p.server, &status);
    EXPECT_EQ(status, Status::EndOfInput);
    EXPECT_EQ(p.server.session().state(), TlsState::Open);
    EXPECT_EQ(p.server.write(bytes_of("owed")).status, Status::Done);
    p.server.shutdown_write();
    EXPECT_EQ(p.server.session().state(), TlsState::Closed);
    EXPECT_EQ(read_text(p.client), "owed");
    read_text(p.client, &status);
    EXPECT_EQ(status, Status::EndOfInput);
}

}  // namespace
}  // namespace mblab::test
