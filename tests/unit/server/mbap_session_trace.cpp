#include "mbap_session_trace.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstring>

#include "support/hex.hpp"

namespace mblab::test {

namespace {

device::Reply exception(std::uint8_t function, std::uint8_t code,
                        std::span<std::uint8_t> response) {
    response[0] = function | 0x80;
    response[1] = code;
    return {device::ReplyAction::Answer, 2, {}};
}

// Holding register N holds N.
device::Reply read_registers(std::span<const std::uint8_t> request,
                             std::span<std::uint8_t> response) {
    if (request.size() != 5) return exception(request[0], 0x03, response);
    const unsigned address = request[1] << 8 | request[2];
    const unsigned count = request[3] << 8 | request[4];
    if (count == 0 || count > 125) return exception(request[0], 0x03, response);
    response[0] = 0x03;
    response[1] = static_cast<std::uint8_t>(2 * count);
    for (unsigned i = 0; i < count; ++i) {
        const auto value = static_cast<std::uint16_t>(address + i);
        response[2 + 2 * i] = static_cast<std::uint8_t>(value >> 8);
        response[3 + 2 * i] = static_cast<std::uint8_t>(value);
    }
    return {device::ReplyAction::Answer, 2 + 2 * count, {}};
}

}  // namespace

device::Reply TraceDevice::handle(const device::RequestContext& context,
                                  std::span<const std::uint8_t> request,
                                  std::span<std::uint8_t> response) {
    if (context.unit == 0) {
        ++broadcasts;
        return {device::ReplyAction::NoAnswer, 0, {}};
    }
    device::Reply reply;
    switch (request[0]) {
        case 0x03:
            return read_registers(request, response);
        case 0x41:
            if (request.size() > 1) reply.delay = std::chrono::milliseconds(10 * request[1]);
            break;
        case 0x42:
            reply.action = device::ReplyAction::NoAnswer;
            return reply;
        case 0x43:
            reply.action = device::ReplyAction::Close;
            return reply;
        default:
            break;
    }
    std::memcpy(response.data(), request.data(), request.size());
    reply.size = request.size();
    return reply;
}

std::optional<device::Reply> TraceDevice::handle_or_defer(const device::RequestContext& context,
                                                          std::span<const std::uint8_t> request,
                                                          std::span<std::uint8_t> response,
                                                          device::Deferral& deferral) {
    if (context.unit != kLineUnit && !(context.unit == 0 && broadcasts_on_line)) {
        return handle(context, request, response);
    }
    line_.push_back({context, {request.begin(), request.end()}, deferral.take()});
    return std::nullopt;
}

void TraceDevice::line_answers() {
    ASSERT_FALSE(line_.empty()) << "no request waits on the line";
    auto job = std::move(line_.front());
    line_.pop_front();
    std::array<std::uint8_t, 253> response{};
    auto context = job.context;
    if (context.unit == kLineUnit) context.unit = 1;
    const auto reply = handle(context, job.pdu, response);
    job.done(reply, std::span(response).first(reply.size));
}

namespace {

// The server's side of the pair: TLS over its end when the trace speaks TLS.
transport::Channel& server_channel(transport::MemoryPair& stream,
                                   const std::unique_ptr<transport::TlsStream>& tls) {
    if (tls) return *tls;
    return stream.server();
}

server::ServerOptions options_for(const TraceTls& tls, std::vector<std::string>& refusals) {
    server::ServerOptions options;
    options.tls = tls.server;
    options.roles = tls.roles;
    options.on_tls_refused = [&refusals](const std::string& why) { refusals.push_back(why); };
    return options;
}

}  // namespace

SessionTrace::SessionTrace(server::MbapSessionLimits limits) : SessionTrace(TraceTls{}, limits) {}

SessionTrace::SessionTrace(const TraceTls& tls, server::MbapSessionLimits limits)
    : options_(options_for(tls, refusals_)),
      server_tls_(tls.server ? std::make_unique<transport::TlsStream>(
                                   stream_.server(), tls.server, transport::TlsStream::Side::Server)
                             : nullptr),
      client_tls_(tls.client ? std::make_unique<transport::TlsStream>(
                                   stream_.client(), tls.client, transport::TlsStream::Side::Client,
                                   "localhost")
                             : nullptr),
      session_(device_, limits, stats_, *this, clock_.now()),
      driver_(server_channel(stream_, server_tls_), session_, options_, stats_, clock_.now()) {
    session_.set_peer("192.0.2.9:50312");
    if (client_tls_) {
        client_tls_->start();
        if (tls.handshake) {
            EXPECT_TRUE(client_handshakes()) << client_tls_->error();
        }
    }
}

transport::Channel& SessionTrace::client_channel() {
    if (client_tls_) return *client_tls_;
    return stream_.client();
}

bool SessionTrace::client_handshakes() {
    for (int round = 0; round < 20 && client_tls_->handshaking(); ++round) {
        run();
        const auto io = client_tls_->handshake();
        if (io.status != transport::Io::Status::Done &&
            io.status != transport::Io::Status::WouldBlock) {
            break;
        }
    }
    run();
    return client_tls_->session().state() == security::TlsChannel::State::Open;
}

device::DeferredDone SessionTrace::route_deferred(std::uint32_t ticket,
                                                  const protocol::MbapHeader& request) {
    return [this, ticket, request](const device::Reply& reply, std::span<const std::uint8_t> pdu) {
        driver_.answer_deferred(ticket, request, reply, pdu, clock_.now());
        run();
    };
}

void SessionTrace::on_own_answer(const device::RequestContext& context,
                                 std::span<const std::uint8_t> request,
                                 protocol::ExceptionCode code) {
    if (code == protocol::ExceptionCode::ServerDeviceBusy) ++busy_replies_;
    own_answers_.push_back("unit " + std::to_string(context.unit) + " from " +
                           std::string(context.peer) + ": " + to_hex(request) + " -> " +
                           to_hex(std::array{static_cast<std::uint8_t>(code)}));
}

void SessionTrace::run() {
    auto& server = stream_.server();
    for (int round = 0; round < 100'000; ++round) {
        if (driver_.closed()) {
            server.close();
            return;
        }
        const auto now = clock_.now();
        const bool out = driver_.wants_write() && server.writable();
        const bool in = driver_.wants_read() && server.readable();
        if (!out && !in) return;
        if (out) driver_.writable(now);
        if (in) driver_.readable(now);
    }
    ADD_FAILURE() << "the driver is never done with what its channel is ready for";
}

void SessionTrace::client_sends(std::string_view hex_bytes) {
    const auto bytes = hex(hex_bytes);
    const auto io = client_channel().write(bytes);
    EXPECT_EQ(io.bytes, bytes.size()) << "the stream refused bytes the client sent";
    run();
}

void SessionTrace::client_sends_byte_by_byte(std::string_view hex_bytes,
                                             std::chrono::milliseconds gap) {
    const auto bytes = hex(hex_bytes);
    for (std::size_t i = 0; i < bytes.size(); ++i) {
        if (i > 0) after(gap);
        client_channel().write(std::span(bytes).subspan(i, 1));
        run();
    }
}

void SessionTrace::client_shuts_down() {
    client_channel().shutdown_write();
    run();
}

void SessionTrace::client_resets() {
    client().reset();
    run();
}

void SessionTrace::after(std::chrono::milliseconds time) {
    const auto until = clock_.now() + time;
    for (int wakeups = 0; !released(); ++wakeups) {
        const auto at = driver_.deadline();
        if (at > until) break;
        if (wakeups == 10'000) {
            ADD_FAILURE() << "the session's deadline does not move on at " << clock_.elapsed();
            break;
        }
        clock_.advance_to(at);
        driver_.on_time(clock_.now());
        run();
    }
    clock_.advance_to(until);
}

std::string SessionTrace::client_reads() {
    run();  // what the client's socket had no room for until now
    std::vector<std::uint8_t> bytes;
    std::array<std::uint8_t, 4096> chunk{};
    for (;;) {
        const auto io = client_channel().read(chunk);
        if (io.status != transport::Io::Status::Done) break;
        bytes.insert(bytes.end(), chunk.begin(), chunk.begin() + io.bytes);
    }
    run();  // the socket has room again
    return to_hex(bytes);
}

std::string SessionTrace::client_reads_everything() {
    std::string all;
    for (auto more = client_reads(); !more.empty(); more = client_reads()) {
        all += all.empty() ? more : " " + more;
    }
    return all;
}

void SessionTrace::device_answers(std::string_view hex_bytes) {
    EXPECT_EQ(client_reads(), to_hex(hex(hex_bytes))) << "at " << clock_.elapsed().count() << " ms";
}

}  // namespace mblab::test
