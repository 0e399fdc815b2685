#include "transport/tls_stream.hpp"

#include <algorithm>
#include <array>
#include <cstring>

namespace mblab::transport {

namespace {
using State = security::TlsChannel::State;
}  // namespace

TlsStream::TlsStream(std::unique_ptr<Channel> lower, const security::SharedContext& context,
                     Side side, std::string_view server_name)
    : owned_(std::move(lower)), lower_(owned_.get()), tls_(context, side, server_name) {}

TlsStream::TlsStream(Channel& lower, const security::SharedContext& context, Side side,
                     std::string_view server_name)
    : lower_(&lower), tls_(context, side, server_name) {}

bool TlsStream::handshaking() const {
    return tls_.state() == State::Handshaking;
}

Io TlsStream::start() {
    tls_.start();
    return flush();
}

Io TlsStream::flush() {
    std::size_t total = 0;
    for (auto out = tls_.output(); !out.empty(); out = tls_.output()) {
        const auto io = lower_->write(out);
        if (io.status == Io::Status::Failed) {
            error_ = lower_->error();
            return io;
        }
        if (io.status != Io::Status::Done || io.bytes == 0) break;  // full: wants_write() says so
        tls_.sent(io.bytes);
        total += io.bytes;
    }
    if (end_owed_ && !wants_write()) {
        end_owed_ = false;
        lower_->shutdown_write();
    }
    return Io::done(total);
}

Io TlsStream::pull() {
    std::array<std::uint8_t, kCipherChunk> cipher;
    const auto io = lower_->read(cipher);
    if (io.status != Io::Status::WouldBlock) heard_ = true;
    if (io.status == Io::Status::Done) tls_.received(std::span(cipher).first(io.bytes));
    if (io.status == Io::Status::Failed) error_ = lower_->error();
    return io;
}

Io TlsStream::ended() {
    if (tls_.state() == State::Closed || tls_.input_ended()) return Io::end_of_input();
    error_ = tls_.error();
    flush();  // the alert that tells the peer why
    return Io::failed();
}

Io TlsStream::handshake() {
    while (tls_.state() == State::Handshaking) {
        if (const auto sent = flush(); sent.status == Io::Status::Failed) return sent;
        const auto io = pull();
        if (io.status == Io::Status::EndOfInput) {
            error_ = "the peer closed the connection during the TLS handshake";
        }
        if (io.status != Io::Status::Done) return io;
        tls_.read({});
    }
    if (tls_.state() != State::Open) return ended();
    // The last flight (and a TLS 1.3 server's tickets): a full lower channel keeps the rest.
    if (const auto sent = flush(); sent.status == Io::Status::Failed) return sent;
    return Io::done(0);
}

Io TlsStream::read(std::span<std::uint8_t> out) {
    if (tls_.state() == State::Handshaking) {
        const auto io = handshake();
        if (io.status != Io::Status::Done) return io;
    }
    if (tls_.has_input()) {
        if (const auto got = tls_.read(out); got > 0) return Io::done(got);
    }
    if (!tls_.input_open()) return ended();
    const auto io = pull();
    if (io.status != Io::Status::Done) return io;
    const auto got = tls_.read(out);
    // A key update's answer, or the close_notify that answers the peer's.
    const auto sent = flush();
    if (got > 0) return Io::done(got);
    if (sent.status == Io::Status::Failed) return sent;
    return tls_.input_open() ? Io::would_block() : ended();
}

Io TlsStream::writev(std::span<const iovec> buffers) {
    if (tls_.state() != State::Open) {
        error_ = tls_.state() == State::Closed ? "the TLS session is closed" : tls_.error();
        return Io::failed();
    }
    if (const auto sent = flush(); sent.status == Io::Status::Failed) return sent;
    if (wants_write()) return Io::would_block();
    std::size_t size = 0;
    bool written = false;
    if (buffers.size() == 1) {
        size = buffers[0].iov_len;
        written = tls_.write({static_cast<const std::uint8_t*>(buffers[0].iov_base), size});
    } else {
        // The buffers go out as one record: a record each would cost a MAC and a header per
        // answer to a pipelining client.
        std::array<std::uint8_t, kPlainBatch> batch;
        for (const auto& buffer : buffers) {
            const auto length = std::min(buffer.iov_len, batch.size() - size);
            if (length == 0) continue;
            std::memcpy(batch.data() + size, buffer.iov_base, length);
            size += length;
        }
        written = tls_.write(std::span(batch).first(size));
    }
    if (!written) {
        error_ = tls_.error();
        flush();
        return Io::failed();
    }
    if (const auto sent = flush(); sent.status == Io::Status::Failed) return sent;
    return Io::done(size);
}

Io TlsStream::close_notify() {
    if (tls_.state() == State::Open) tls_.close();
    return flush();
}

void TlsStream::shutdown_write() {
    // The lower end goes once the close_notify is all out: a FIN in the middle of its record is
    // a truncation, which the peer's TLS reports as an attack, not as the end of the session.
    end_owed_ = true;
    close_notify();
}

PeerIdentity TlsStream::peer() const {
    auto identity = lower_->peer();
    // Only a session that opened has a peer worth the name.
    if (tls_.state() == State::Open || tls_.state() == State::Closed) identity.tls = &tls_.peer();
    return identity;
}

}  // namespace mblab::transport
