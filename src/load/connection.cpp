#include "load/connection.hpp"

#include <fmt/core.h>
#include <sys/epoll.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <cstring>

#include "protocol/limits.hpp"
#include "protocol/mbap_header.hpp"

namespace mblab::load {

namespace {

namespace limits = protocol::limits;
using Status = transport::Io::Status;
using TlsState = security::TlsChannel::State;

// A refused or dropped connection is tried again after this; long enough not to spin on a
// device that is down, short enough to keep loading one that closes connections on purpose.
constexpr std::chrono::milliseconds kReconnectDelay{100};
constexpr std::size_t kMinInput = 4096;

const char* socket_error_text(int code) {
    switch (code) {
        case ECONNREFUSED:
            return "connection refused";
        case ECONNRESET:
            return "connection reset by the device";
        case EPIPE:
            return "connection closed by the device";
        case ETIMEDOUT:
            return "connection timed out";
        default:
            return std::strerror(code);
    }
}

}  // namespace

LoadConnection::LoadConnection(WorkerContext& context, NodeTally& tally, std::size_t node,
                               Role role, std::uint64_t seed)
    : context_(context),
      tally_(tally),
      target_(context.plan.targets[node]),
      role_(role),
      prng_(seed),
      port_(context.ports.make(target_, this)) {
    window_ = role == Role::Tests ? 1 : std::max<std::size_t>(1, context.plan.settings.pipeline);
    slot_bits_ = static_cast<unsigned>(std::bit_width(window_ - 1));
    slots_.resize(window_);
    for (std::size_t i = window_; i > 0; --i) {
        free_slots_.push_back(static_cast<std::uint16_t>(i - 1));
    }
    in_.resize(std::max(kMinInput, (window_ + 1) * limits::kMaxTcpAdu));
    out_.resize(window_ * limits::kMaxTcpAdu);
}

LoadConnection::~LoadConnection() {
    SSL_SESSION_free(session_);
}

bool LoadConnection::settled() const {
    return state_ == State::Done || (state_ == State::Open && outstanding_ == 0);
}

void LoadConnection::connect(LoadClock::time_point now) {
    int error = 0;
    const auto dial = port_->dial(error);
    if (dial == ConnectionPort::Dial::Failed) {
        disconnect(now);
        fail(FailureKind::Refused, nullptr,
             {client::ReceiveStatus::Closed, {}, socket_error_text(error)}, now,
             "cannot connect: ");
        return;
    }
    channel_ = port_->take_channel();
    state_ = State::Connecting;
    connect_deadline_ = now + context_.plan.settings.timeout;
    if (dial == ConnectionPort::Dial::Open) {
        opened(now);
        return;
    }
    want_write_ = true;
    port_->watch(true);
}

void LoadConnection::finish_connect(LoadClock::time_point now) {
    if (const int code = port_->dial_result(); code != 0) {
        disconnect(now);
        fail(FailureKind::Refused, nullptr,
             {client::ReceiveStatus::Closed, {}, socket_error_text(code)}, now, "cannot connect: ");
        return;
    }
    opened(now);
}

void LoadConnection::opened(LoadClock::time_point now) {
    want_write_ = false;
    port_->watch(false);
    if (target_.tls) {
        start_tls(now);
        return;
    }
    start_traffic(now);
}

void LoadConnection::start_tls(LoadClock::time_point now) {
    state_ = State::Handshaking;
    auto stream = std::make_unique<transport::TlsStream>(std::move(channel_), target_.tls->context,
                                                         transport::TlsStream::Side::Client,
                                                         target_.tls->server_name);
    stream->session().offer_session(session_);
    tls_ = stream.get();
    channel_ = std::move(stream);
    if (const auto io = tls_->start(); io.status == Status::Failed) {
        lost(now, socket_error_text(io.code));
        return;
    }
    set_write_interest(tls_->wants_write());
}

void LoadConnection::handshake(LoadClock::time_point now) {
    const auto io = tls_->handshake();
    switch (io.status) {
        case Status::WouldBlock:
            set_write_interest(tls_->wants_write());
            return;
        case Status::Done:
            set_write_interest(tls_->wants_write());
            tally_.handshakes.add();
            if (tls_->session().peer().resumed) tally_.resumed.add();
            start_traffic(now);
            return;
        case Status::EndOfInput:
            lost(now, "connection closed by the device");
            return;
        case Status::Failed:
            break;
    }
    if (io.code != 0) {
        lost(now, socket_error_text(io.code));
        return;
    }
    const std::string why = "TLS handshake: " + tls_->error();
    disconnect(now);
    fail(FailureKind::Refused, nullptr, {client::ReceiveStatus::Closed, {}, why}, now,
         "cannot connect: ");
}

void LoadConnection::start_traffic(LoadClock::time_point now) {
    state_ = State::Open;
    const auto interval = context_.send_interval;
    if (interval.count() > 0) {
        // Spread the connections' sends over the interval rather than all at once.
        next_send_ = now + interval * static_cast<long>(prng_.next() % 1000) / 1000;
    }
    fill(now);
}

void LoadConnection::disconnect(LoadClock::time_point now) {
    if (tls_) {
        // close_notify keeps the session resumable, and the device sees an orderly end.
        if (tls_->session().state() == TlsState::Open && port_->connected()) {
            tls_->close_notify();
        }
        if (SSL_SESSION* session = tls_->session().take_session()) {
            SSL_SESSION_free(session_);
            session_ = session;
        }
        tls_ = nullptr;
    }
    port_->release();
    channel_.reset();  // closes the connection
    for (auto& slot : slots_) {
        if (slot.active) release(slot);
        slot.has_expired = false;
    }
    in_begin_ = in_end_ = out_begin_ = out_end_ = 0;
    want_write_ = false;
    earliest_deadline_ = LoadClock::time_point::max();
    state_ = context_.running ? State::Closed : State::Done;
    retry_at_ = now + kReconnectDelay;
}

void LoadConnection::lost(LoadClock::time_point now, const char* detail) {
    fail(FailureKind::Dropped, oldest_slot(), {client::ReceiveStatus::Closed, held(), detail}, now);
    disconnect(now);
}

void LoadConnection::on_event(std::uint32_t events, LoadClock::time_point now) {
    if (state_ == State::Connecting) {
        if ((events & (EPOLLOUT | EPOLLERR | EPOLLHUP)) != 0) finish_connect(now);
        return;
    }
    if (state_ == State::Handshaking) {
        handshake(now);  // sends what waits for room, then reads
        return;
    }
    if (state_ != State::Open) return;
    if ((events & (EPOLLIN | EPOLLERR | EPOLLHUP)) != 0) read(now);
    if (state_ == State::Open && (events & EPOLLOUT) != 0) flush(now);
}

void LoadConnection::tick(LoadClock::time_point now) {
    switch (state_) {
        case State::Closed:
            if (!context_.running) {
                state_ = State::Done;
            } else if (now >= retry_at_) {
                connect(now);
            }
            return;
        case State::Connecting:
        case State::Handshaking:
            if (!context_.running) {
                disconnect(now);
            } else if (now >= connect_deadline_) {
                disconnect(now);
                fail(FailureKind::Refused, nullptr,
                     {client::ReceiveStatus::Timeout, {}, "no answer to the connection request"},
                     now, "cannot connect: ");
            }
            return;
        case State::Open:
            if (now >= earliest_deadline_) expire(now);
            fill(now);
            return;
        case State::Done:
            return;
    }
}

void LoadConnection::flush(LoadClock::time_point now) {
    // Over TLS the requests are taken whole, as one record; its bytes go out as the device
    // takes them.
    while (out_begin_ < out_end_ || channel_->wants_write()) {
        const bool requests = out_begin_ < out_end_;
        const auto io = requests
                            ? channel_->write({out_.data() + out_begin_, out_end_ - out_begin_})
                            : channel_->flush();
        if (io.status == Status::Failed) {
            lost(now, io.code != 0 ? socket_error_text(io.code) : "the TLS session failed");
            return;
        }
        if (io.bytes == 0) {
            set_write_interest(true);
            return;
        }
        if (requests) out_begin_ += io.bytes;
    }
    out_begin_ = out_end_ = 0;
    set_write_interest(false);
}

void LoadConnection::set_write_interest(bool want) {
    if (want == want_write_) return;
    want_write_ = want;
    port_->watch(want);
}

bool LoadConnection::receive(LoadClock::time_point now) {
    if (in_end_ == in_.size()) {  // only a partial frame at the front can be held: compact
        std::memmove(in_.data(), in_.data() + in_begin_, in_end_ - in_begin_);
        in_end_ -= in_begin_;
        in_begin_ = 0;
    }
    bool got = false;
    auto io = channel_->read({in_.data() + in_end_, in_.size() - in_end_});
    // Records decrypted past the first read are taken now: no socket event would bring them.
    while (io.status == Status::Done) {
        got = true;
        in_end_ += io.bytes;
        if (!channel_->has_input() || in_end_ == in_.size()) break;
        io = channel_->read({in_.data() + in_end_, in_.size() - in_end_});
    }
    if (tls_ && tls_->session().state() != TlsState::Open) {
        // A device that refuses the certificate after a TLS 1.3 handshake says so only now.
        const std::string why = tls_->session().state() == TlsState::Closed
                                    ? "the device ended the TLS session"
                                    : "TLS: " + tls_->error();
        fail(FailureKind::Dropped, oldest_slot(), {client::ReceiveStatus::Closed, held(), why},
             now);
        disconnect(now);
        return false;
    }
    // What came before an end is judged first; the end is read again at the next wake-up.
    if (got || io.status == Status::WouldBlock) return got;
    lost(now, io.status == Status::EndOfInput ? "connection closed by the device"
                                              : socket_error_text(io.code));
    return false;
}

void LoadConnection::read(LoadClock::time_point now) {
    if (!receive(now)) return;
    while (in_begin_ < in_end_) {
        std::size_t consumed = 0;
        const protocol::FrameEvent event = framer_.feed(held(), consumed);
        if (event.status == protocol::FrameStatus::NeedMore) {
            // The framer copied the unfinished frame; it stays in in_ instead, where a failure's
            // evidence shows it, and is fed whole once the rest has come.
            framer_.reset();
            break;
        }
        if (event.is_error() && event.adu.empty()) {
            // A length no frame has: the stream cannot be split into frames any more, so start a
            // fresh connection.
            fail(FailureKind::Malformed, oldest_slot(),
                 {client::ReceiveStatus::Malformed, held(),
                  "the MBAP length field cannot describe an answer (2..254)"},
                 now);
            disconnect(now);
            return;
        }
        // A whole frame, also one the framer refuses for its protocol id: judged as an answer
        // (malformed), and it still takes its request's place.
        answer(event.adu, now);
        in_begin_ += consumed;
    }
    if (in_begin_ == in_end_) {
        in_begin_ = in_end_ = 0;
    } else if (in_.size() - in_end_ < limits::kMaxTcpAdu) {
        std::memmove(in_.data(), in_.data() + in_begin_, in_end_ - in_begin_);
        in_end_ -= in_begin_;
        in_begin_ = 0;
    }
    fill(now);
}

}  // namespace mblab::load
