#include "load/connection.hpp"

#include <fmt/core.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/epoll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <cstring>

#include "protocol/adu_writer.hpp"
#include "protocol/limits.hpp"
#include "protocol/mbap_header.hpp"

namespace mblab::load {

namespace {

namespace limits = protocol::limits;
using std::chrono::duration_cast;
using std::chrono::microseconds;

// A refused or dropped connection is tried again after this; long enough not to spin on a
// device that is down, short enough to keep loading one that closes connections on purpose.
constexpr std::chrono::milliseconds kReconnectDelay{100};
constexpr std::size_t kMinInput = 4096;
constexpr std::chrono::milliseconds kMaxSendDebt{50};

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

// Level-triggered: a connection reads once per wake-up and is woken again while bytes remain.
std::uint32_t interest(bool want_write) {
    return EPOLLIN | (want_write ? std::uint32_t{EPOLLOUT} : 0U);
}

}  // namespace

LoadConnection::LoadConnection(WorkerContext& context, NodeTally& tally, std::size_t node,
                               Role role, std::uint64_t seed)
    : context_(context),
      tally_(tally),
      target_(context.plan.targets[node]),
      role_(role),
      prng_(seed) {
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
    if (fd_ >= 0) ::close(fd_);
    SSL_SESSION_free(session_);
}

bool LoadConnection::settled() const {
    return state_ == State::Done || (state_ == State::Open && outstanding_ == 0);
}

void LoadConnection::connect(LoadClock::time_point now) {
    const auto& address = target_.address;
    fd_ = ::socket(address.ss_family, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    if (fd_ < 0) {
        fail(FailureKind::Refused, nullptr,
             {client::ReceiveStatus::Closed, {}, std::strerror(errno)}, now,
             "cannot open a socket: ");
        state_ = State::Closed;
        retry_at_ = now + kReconnectDelay;
        return;
    }
    int one = 1;
    ::setsockopt(fd_, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
    state_ = State::Connecting;
    connect_deadline_ = now + context_.plan.settings.timeout;
    if (::connect(fd_, reinterpret_cast<const sockaddr*>(&address), target_.address_size) == 0) {
        opened(now);
        return;
    }
    if (errno != EINPROGRESS) {
        const int code = errno;
        disconnect(now);
        fail(FailureKind::Refused, nullptr,
             {client::ReceiveStatus::Closed, {}, socket_error_text(code)}, now, "cannot connect: ");
        return;
    }
    want_write_ = true;
    context_.epoll.add(fd_, this, interest(true));
}

void LoadConnection::finish_connect(LoadClock::time_point now) {
    int code = 0;
    socklen_t size = sizeof code;
    if (::getsockopt(fd_, SOL_SOCKET, SO_ERROR, &code, &size) != 0) code = errno;
    if (code != 0) {
        disconnect(now);
        fail(FailureKind::Refused, nullptr,
             {client::ReceiveStatus::Closed, {}, socket_error_text(code)}, now, "cannot connect: ");
        return;
    }
    opened(now);
}

void LoadConnection::opened(LoadClock::time_point now) {
    const bool registered = want_write_;
    want_write_ = false;
    if (registered) {
        context_.epoll.modify(fd_, this, interest(false));
    } else {
        context_.epoll.add(fd_, this, interest(false));
    }
    if (target_.tls) {
        start_tls(now);
        return;
    }
    start_traffic(now);
}

void LoadConnection::start_tls(LoadClock::time_point now) {
    state_ = State::Handshaking;
    tls_ = std::make_unique<security::TlsChannel>(
        target_.tls->context, security::TlsChannel::Side::Client, target_.tls->server_name);
    tls_->offer_session(session_);
    tls_->start();
    send_cipher(now);
}

void LoadConnection::handshake(LoadClock::time_point now) {
    if (!receive(now) || state_ != State::Handshaking) return;
    using TlsState = security::TlsChannel::State;
    switch (tls_->state()) {
        case TlsState::Handshaking:
            send_cipher(now);
            return;
        case TlsState::Open:
            if (!send_cipher(now)) return;
            tally_.handshakes.add();
            if (tls_->peer().resumed) tally_.resumed.add();
            start_traffic(now);
            return;
        case TlsState::Closed:
        case TlsState::Failed: {
            const std::string why = "TLS handshake: " + tls_->error();
            send_cipher(now);
            disconnect(now);
            fail(FailureKind::Refused, nullptr, {client::ReceiveStatus::Closed, {}, why}, now,
                 "cannot connect: ");
            return;
        }
    }
}

bool LoadConnection::send_cipher(LoadClock::time_point now) {
    for (auto out = tls_->output(); !out.empty(); out = tls_->output()) {
        const ssize_t n = ::send(fd_, out.data(), out.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
        if (n > 0) {
            tls_->sent(static_cast<std::size_t>(n));
            continue;
        }
        if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
            set_write_interest(true);
            return true;
        }
        if (n < 0 && errno == EINTR) continue;
        lost(now, socket_error_text(n < 0 ? errno : EPIPE));
        return false;
    }
    set_write_interest(false);
    return true;
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
        if (tls_->state() == security::TlsChannel::State::Open && fd_ >= 0) {
            // close_notify keeps the session resumable, and the device sees an orderly end.
            tls_->close();
            const auto out = tls_->output();
            if (!out.empty()) ::send(fd_, out.data(), out.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
        }
        if (SSL_SESSION* session = tls_->take_session()) {
            SSL_SESSION_free(session_);
            session_ = session;
        }
        tls_.reset();
    }
    if (fd_ >= 0) {
        context_.epoll.remove(fd_);
        ::close(fd_);
        fd_ = -1;
    }
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
        if ((events & EPOLLOUT) != 0 && !send_cipher(now)) return;
        if ((events & (EPOLLIN | EPOLLERR | EPOLLHUP)) != 0) handshake(now);
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

bool LoadConnection::next_exchange(std::uint32_t& out) {
    if (role_ == Role::Traffic) {
        out = next_mix_exchange(context_.plan, prng_);
        return true;
    }
    return next_test_exchange(context_.plan, tally_, test_cursor_, out);
}

LoadConnection::Slot& LoadConnection::take_slot() {
    const std::uint16_t index = free_slots_.back();
    free_slots_.pop_back();
    Slot& slot = slots_[index];
    ++slot.generation;
    const unsigned generation_bits = 16 - slot_bits_;
    const auto generation = static_cast<std::uint16_t>(
        generation_bits >= 16 ? slot.generation : slot.generation & ((1U << generation_bits) - 1));
    slot.tid = static_cast<std::uint16_t>((generation << slot_bits_) | index);
    slot.active = true;
    ++outstanding_;
    return slot;
}

void LoadConnection::release(Slot& slot) {
    slot.active = false;
    --outstanding_;
    free_slots_.push_back(static_cast<std::uint16_t>(&slot - slots_.data()));
}

LoadConnection::Slot* LoadConnection::find_slot(std::uint16_t tid) {
    const std::size_t index = tid & ((1U << slot_bits_) - 1);
    if (index >= slots_.size()) return nullptr;
    Slot& slot = slots_[index];
    return slot.active && slot.tid == tid ? &slot : nullptr;
}

LoadConnection::Slot* LoadConnection::oldest_slot() {
    Slot* oldest = nullptr;
    for (auto& slot : slots_) {
        if (slot.active && (oldest == nullptr || slot.sent_at < oldest->sent_at)) oldest = &slot;
    }
    return oldest;
}

void LoadConnection::fill(LoadClock::time_point now) {
    if (!context_.running || state_ != State::Open) return;
    const auto interval = context_.send_interval;
    const auto timeout = context_.plan.settings.timeout;
    while (outstanding_ < window_) {
        if (interval.count() > 0) {
            if (now < next_send_) break;
            // Sends wait for the next tick (a millisecond or more on a busy machine), so some
            // lag is made up later; but after a real stall the debt is forgiven rather than
            // paid back as a burst.
            const auto debt = std::max<std::chrono::nanoseconds>(
                interval * static_cast<long>(window_), kMaxSendDebt);
            if (next_send_ + debt < now) next_send_ = now - debt;
            next_send_ += interval;
        }
        std::uint32_t index = 0;
        if (!next_exchange(index)) break;
        const auto& request = context_.plan.exchanges[index].request;
        if (out_end_ + request.size() > out_.size()) break;
        Slot& slot = take_slot();
        slot.exchange = index;
        slot.sent_at = now;
        earliest_deadline_ = std::min(earliest_deadline_, now + timeout);
        std::memcpy(out_.data() + out_end_, request.data(), request.size());
        protocol::put_mbap_transaction_id({out_.data() + out_end_, request.size()}, slot.tid);
        out_end_ += request.size();
        tally_.sent.add();
        tally_.exchange(index).sent.add();
    }
    flush(now);
}

void LoadConnection::flush(LoadClock::time_point now) {
    if (tls_) {
        if (out_begin_ < out_end_ &&
            !tls_->write({out_.data() + out_begin_, out_end_ - out_begin_})) {
            lost(now, "the TLS session failed");
            return;
        }
        out_begin_ = out_end_ = 0;
        send_cipher(now);
        return;
    }
    while (out_begin_ < out_end_) {
        const ssize_t n = ::send(fd_, out_.data() + out_begin_, out_end_ - out_begin_,
                                 MSG_NOSIGNAL | MSG_DONTWAIT);
        if (n > 0) {
            out_begin_ += static_cast<std::size_t>(n);
            continue;
        }
        if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
            set_write_interest(true);
            return;
        }
        if (n < 0 && errno == EINTR) continue;
        lost(now, socket_error_text(n < 0 ? errno : EPIPE));
        return;
    }
    out_begin_ = out_end_ = 0;
    set_write_interest(false);
}

void LoadConnection::set_write_interest(bool want) {
    if (want == want_write_) return;
    want_write_ = want;
    context_.epoll.modify(fd_, this, interest(want));
}

bool LoadConnection::receive(LoadClock::time_point now) {
    if (in_end_ == in_.size()) {  // only a partial frame at the front can be held: compact
        std::memmove(in_.data(), in_.data() + in_begin_, in_end_ - in_begin_);
        in_end_ -= in_begin_;
        in_begin_ = 0;
    }
    std::array<std::uint8_t, 16 * 1024 + 512> cipher;
    const auto into = tls_ ? std::span<std::uint8_t>(cipher)
                           : std::span<std::uint8_t>(in_.data() + in_end_, in_.size() - in_end_);
    const ssize_t n = ::recv(fd_, into.data(), into.size(), MSG_DONTWAIT);
    if (n == 0) {
        lost(now, "connection closed by the device");
        return false;
    }
    if (n < 0) {
        if (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR) {
            lost(now, socket_error_text(errno));
        }
        return false;
    }
    if (!tls_) {
        in_end_ += static_cast<std::size_t>(n);
        return true;
    }
    tls_->received(into.first(static_cast<std::size_t>(n)));
    while (std::size_t got = tls_->read({in_.data() + in_end_, in_.size() - in_end_})) {
        in_end_ += got;
    }
    if (state_ == State::Open && tls_->state() != security::TlsChannel::State::Open) {
        // A device that refuses the certificate after a TLS 1.3 handshake says so only now.
        const std::string why = tls_->state() == security::TlsChannel::State::Closed
                                    ? "the device ended the TLS session"
                                    : "TLS: " + tls_->error();
        fail(FailureKind::Dropped, oldest_slot(), {client::ReceiveStatus::Closed, held(), why},
             now);
        disconnect(now);
        return false;
    }
    return true;
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

void LoadConnection::answer(std::span<const std::uint8_t> frame, LoadClock::time_point now) {
    const std::uint16_t tid = protocol::read_mbap_header(frame).transaction_id;
    Slot* slot = find_slot(tid);
    bool tid_matches = slot != nullptr;
    if (slot == nullptr) {
        const std::size_t index = tid & ((1U << slot_bits_) - 1);
        if (index < slots_.size() && slots_[index].has_expired &&
            slots_[index].expired_tid == tid) {
            slots_[index].has_expired = false;
            tally_.late.add();
            return;
        }
        // Modbus/TCP servers answer in order: take it as the answer to the oldest request.
        slot = oldest_slot();
    }
    tally_.answered.add();
    if (slot == nullptr) {
        fail(FailureKind::WrongAnswer, nullptr, {client::ReceiveStatus::Frame, frame, {}}, now,
             "an answer that no request asked for");
        return;
    }
    tally_.latency.record(
        static_cast<std::uint64_t>(duration_cast<microseconds>(now - slot->sent_at).count()));
    std::optional<FailureKind> failure =
        tid_matches
            ? judge_load_answer(context_.plan, tally_, role_ == Role::Tests, slot->exchange, frame)
            : FailureKind::WrongAnswer;
    if (failure) fail(*failure, slot, {client::ReceiveStatus::Frame, frame, {}}, now);
    release(*slot);
}

void LoadConnection::expire(LoadClock::time_point now) {
    const auto timeout = context_.plan.settings.timeout;
    earliest_deadline_ = LoadClock::time_point::max();
    for (auto& slot : slots_) {
        if (!slot.active) continue;
        const auto deadline = slot.sent_at + timeout;
        if (deadline > now) {
            earliest_deadline_ = std::min(earliest_deadline_, deadline);
            continue;
        }
        fail(FailureKind::Timeout, &slot, {client::ReceiveStatus::Timeout, held(), {}}, now);
        slot.expired_tid = slot.tid;
        slot.has_expired = true;
        release(slot);
    }
}

void LoadConnection::fail(FailureKind kind, const Slot* slot, const LoadSeen& seen,
                          LoadClock::time_point now, std::string_view reason) {
    if (slot == nullptr) {
        count_failure(tally_, context_.plan, context_.start, kind, nullptr, seen, now, reason);
        return;
    }
    const LoadSent sent{slot->exchange, slot->tid};
    count_failure(tally_, context_.plan, context_.start, kind, &sent, seen, now, reason);
}

}  // namespace mblab::load
