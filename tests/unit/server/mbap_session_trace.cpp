#include "mbap_session_trace.hpp"

#include <gtest/gtest.h>
#include <sys/uio.h>

#include <algorithm>
#include <array>
#include <cstring>

#include "support/hex.hpp"

namespace mblab::test {

namespace {

using Ending = server::MbapSession::Ending;

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

SessionTrace::SessionTrace(server::MbapSessionLimits limits)
    : session_(device_, limits, stats_, *this, clock_.now()) {}

device::DeferredDone SessionTrace::route_deferred(std::uint32_t ticket,
                                                  const protocol::MbapHeader& request) {
    return [this, ticket, request](const device::Reply& reply, std::span<const std::uint8_t> pdu) {
        if (closed_) return;
        session_.answer_deferred(ticket, request, reply, pdu, clock_.now());
        run();
    };
}

void SessionTrace::on_busy_reply(std::uint8_t /*unit*/) {
    ++busy_replies_;
}

void SessionTrace::run() {
    auto& server = stream_.server();
    while (!closed_) {
        flush();
        if (closed_ || !session_.wants_input()) return;
        const auto io = server.read(session_.input_space());
        switch (io.status) {
            case StreamIo::Status::Done:
                session_.received(io.bytes, clock_.now());
                break;
            case StreamIo::Status::EndOfInput:
                session_.end_of_input(clock_.now());
                break;
            case StreamIo::Status::WouldBlock:
                return;
            case StreamIo::Status::Reset:
                close(false);
                return;
        }
    }
}

void SessionTrace::flush() {
    auto& server = stream_.server();
    if (write_blocked_ && server.writable()) write_blocked_ = false;
    std::array<iovec, server::MbapSession::kMaxGather> gathered;
    std::array<std::span<const std::uint8_t>, server::MbapSession::kMaxGather> buffers;
    while (!closed_ && !write_blocked_) {
        const auto now = clock_.now();
        const auto count = session_.output(now, gathered);
        if (count == 0) {
            const auto ending = session_.ending(now);
            if (ending != Ending::Open) close(ending == Ending::AfterAnswers);
            return;
        }
        std::size_t wanted = 0;
        for (std::size_t i = 0; i < count; ++i) {
            buffers[i] = {static_cast<const std::uint8_t*>(gathered[i].iov_base),
                          gathered[i].iov_len};
            wanted += gathered[i].iov_len;
        }
        const auto io = server.write(std::span(buffers).first(count));
        if (io.status == StreamIo::Status::Reset) {
            close(false);
            return;
        }
        session_.sent(io.bytes, now);
        if (io.bytes < wanted) write_blocked_ = true;
    }
}

void SessionTrace::close(bool /*after_answers*/) {
    closed_ = true;
    if (!stream_.server().is_reset()) stream_.server().shutdown_write();
}

void SessionTrace::client_sends(std::string_view hex_bytes) {
    const auto bytes = hex(hex_bytes);
    const auto io = client().write(bytes);
    EXPECT_EQ(io.bytes, bytes.size()) << "the stream refused bytes the client sent";
    run();
}

void SessionTrace::client_sends_byte_by_byte(std::string_view hex_bytes,
                                             std::chrono::milliseconds gap) {
    const auto bytes = hex(hex_bytes);
    for (std::size_t i = 0; i < bytes.size(); ++i) {
        if (i > 0) after(gap);
        client().write(std::span(bytes).subspan(i, 1));
        run();
    }
}

void SessionTrace::client_shuts_down() {
    client().shutdown_write();
    run();
}

void SessionTrace::client_resets() {
    client().reset();
    run();
}

void SessionTrace::after(std::chrono::milliseconds time) {
    const auto until = clock_.now() + time;
    for (int wakeups = 0; !closed_; ++wakeups) {
        const auto at = session_.deadline();
        if (at > until) break;
        if (wakeups == 10'000) {
            ADD_FAILURE() << "the session's deadline does not move on at " << clock_.elapsed();
            break;
        }
        clock_.advance_to(at);
        session_.on_time(clock_.now());
        if (session_.ending(clock_.now()) == Ending::Now) {
            close(false);
            break;
        }
        run();
    }
    clock_.advance_to(until);
}

std::string SessionTrace::client_reads() {
    run();  // what the client's socket had no room for until now
    std::vector<std::uint8_t> bytes;
    std::array<std::uint8_t, 4096> chunk{};
    for (;;) {
        const auto io = client().read(chunk);
        if (io.status != StreamIo::Status::Done) break;
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
