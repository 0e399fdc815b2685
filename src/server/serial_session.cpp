#include "server/serial_session.hpp"

#include <algorithm>
#include <asio/write.hpp>
#include <type_traits>

#include "transport/tcp_url.hpp"

namespace mblab::server {

namespace {

template <class Stream>
constexpr bool kIsSerialPort = std::is_same_v<Stream, asio::serial_port>;

template <class Stream>
constexpr LineCarrier kCarrier = kIsSerialPort<Stream> ? LineCarrier::SerialPort : LineCarrier::Tcp;

}  // namespace

std::string line_failure_text(const asio::error_code& ec) {
    if (ec == asio::error::eof || ec == std::errc::io_error) return "the line hung up";
    return ec.message();
}

template <class Stream>
LineSession<Stream>::LineSession(Stream stream, std::shared_ptr<ServerCore> core, LineSetup setup)
    : stream_(std::move(stream)),
      core_(std::move(core)),
      on_failure_(std::move(setup.on_failure)),
      line_(core_->handler, setup, kCarrier<Stream>,
            {core_->options.partial_frame_timeout, core_->options.frame_limit}, core_->stats,
            LineClock::now()),
      timer_(stream_.get_executor()),
      pace_(setup.pace),
      pace_timer_(stream_.get_executor()) {
    if constexpr (kIsSerialPort<Stream>) {
        faults_.emplace(stream_.native_handle());
    } else {
        asio::error_code ec;
        const auto peer = stream_.remote_endpoint(ec);
        if (!ec) line_.set_peer(transport::endpoint_text(peer));
    }
}

template <class Stream>
LineSession<Stream>::~LineSession() {
    leave_table();
}

template <class Stream>
void LineSession<Stream>::leave_table() {
    if (!in_table_) return;
    in_table_ = false;
    core_->listener->connections().remove(*this);
    core_->stats.connections_open.fetch_sub(1, std::memory_order_relaxed);
}

template <class Stream>
void LineSession<Stream>::start() {
    if (core_->listener) {
        core_->listener->connections().add(*this);
        in_table_ = true;
        ServerStats::bump(core_->stats.connections_open);
    }
    settle();
}

template <class Stream>
transport::Standing LineSession<Stream>::standing(LineClock::time_point now) const {
    if (closed_) return transport::Standing::Busy;
    if (linger_.active()) return transport::Standing::Ending;
    return line_.standing(now);
}

template <class Stream>
void LineSession<Stream>::close() {
    if (closed_) return;
    closed_ = true;
    asio::error_code ignored;
    stream_.close(ignored);
    // Its place is free now, not once its pending operations have ended.
    leave_table();
    timer_.cancel();
    pace_timer_.cancel();
}

template <class Stream>
void LineSession<Stream>::fail(const std::string& why) {
    if (!closed_ && on_failure_) on_failure_(why);
    close();
}

template <class Stream>
void LineSession<Stream>::settle() {
    if (closed_) return;
    const auto now = LineClock::now();
    line_.on_time(now);
    if (line_.ending()) {
        end();
        return;
    }
    if (!writing_) {
        if (const auto answer = line_.output(now); !answer.empty()) write(answer);
    }
    if (!reading_ && line_.wants_input()) read();
    arm_timer(line_.deadline());
}

template <class Stream>
void LineSession<Stream>::end() {
    if constexpr (kIsSerialPort<Stream>) {
        close();
    } else {
        // An answer still being written goes out first; written() comes back here.
        if (writing_) return;
        const auto now = LineClock::now();
        if (!linger_.active()) {
            if (input_ended_) {
                close();
                return;
            }
            asio::error_code ignored;
            stream_.shutdown(asio::ip::tcp::socket::shutdown_send, ignored);
            linger_.start(now);
        }
        if (linger_.over(now)) {
            close();
            return;
        }
        if (!reading_) read();
        arm_timer(linger_.deadline());
    }
}

template <class Stream>
void LineSession<Stream>::discarded(const asio::error_code& ec) {
    // The client's end, or a reset: nothing can reset the answers any more.
    if (ec) {
        close();
        return;
    }
    linger_.heard(LineClock::now());
    end();
}

template <class Stream>
void LineSession<Stream>::read() {
    reading_ = true;
    const auto space = line_.input_space();
    stream_.async_read_some(
        asio::buffer(space.data(), space.size()),
        [self = this->shared_from_this()](const asio::error_code& ec, std::size_t size) {
            self->reading_ = false;
            if (self->closed_ || ec == asio::error::operation_aborted) return;
            if (self->linger_.active()) {
                self->discarded(ec);
                return;
            }
            if (ec == asio::error::eof && !kIsSerialPort<Stream>) {
                self->input_ended_ = true;
                self->line_.end_of_input();
            } else if (ec) {
                self->fail(line_failure_text(ec));
                return;
            } else {
                self->count_line_faults();
                self->line_.received(size, LineClock::now());
            }
            self->settle();
        });
}

template <class Stream>
void LineSession<Stream>::write(std::span<const std::uint8_t> answer) {
    writing_ = true;
    if (pace_.count() > 0) {
        write_paced(answer, 0, LineClock::now());
        return;
    }
    asio::async_write(
        stream_, asio::buffer(answer.data(), answer.size()),
        [self = this->shared_from_this()](const asio::error_code& ec, std::size_t /*written*/) {
            self->written(ec);
        });
}

template <class Stream>
void LineSession<Stream>::write_paced(std::span<const std::uint8_t> answer, std::size_t index,
                                      LineClock::time_point start) {
    if (index == answer.size()) {
        written({});
        return;
    }
    // The answer is the core's until sent(), so the span stays valid across the waits. The far
    // end has a character once its stop bit is in: character i goes at start + (i + 1)
    // character times.
    pace_timer_.expires_at(start + pace_ * static_cast<long>(index + 1));
    pace_timer_.async_wait(
        [self = this->shared_from_this(), answer, index, start](const asio::error_code& wait) {
            if (self->closed_ || wait) return;
            // Every character due by now goes at once, so a late wake-up never opens a silence.
            const auto due = static_cast<std::size_t>((LineClock::now() - start) / self->pace_);
            const std::size_t next = std::clamp(due, index + 1, answer.size());
            asio::async_write(self->stream_, asio::buffer(answer.data() + index, next - index),
                              [self, answer, next, start](const asio::error_code& ec, std::size_t) {
                                  if (ec) {
                                      self->written(ec);
                                      return;
                                  }
                                  if (!self->closed_) self->write_paced(answer, next, start);
                              });
        });
}

template <class Stream>
void LineSession<Stream>::written(const asio::error_code& ec) {
    writing_ = false;
    if (closed_) return;
    if (ec) {
        fail(kIsSerialPort<Stream> ? line_failure_text(ec) : ec.message());
        return;
    }
    line_.sent(LineClock::now());
    settle();
}

template <class Stream>
void LineSession<Stream>::arm_timer(LineClock::time_point at) {
    if (at == timer_at_) return;
    timer_at_ = at;
    if (at == LineClock::time_point::max()) {
        timer_.cancel();
        return;
    }
    timer_.expires_at(at);
    timer_.async_wait([self = this->shared_from_this()](const asio::error_code& ec) {
        if (ec) return;  // set again or closed
        self->timer_at_ = LineClock::time_point::max();
        self->settle();
    });
}

template <class Stream>
void LineSession<Stream>::count_line_faults() {
    if (!faults_) return;
    const auto faults = faults_->poll();
    line_.line_faults(faults.overruns, faults.parity_errors);
}

template class LineSession<asio::serial_port>;
template class LineSession<asio::ip::tcp::socket>;

}  // namespace mblab::server
