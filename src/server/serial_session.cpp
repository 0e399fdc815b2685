#include "server/serial_session.hpp"

#include <algorithm>
#include <asio/co_spawn.hpp>
#include <asio/detached.hpp>
#include <asio/experimental/as_tuple.hpp>
#include <asio/use_awaitable.hpp>
#include <asio/write.hpp>
#include <type_traits>

#include "protocol/adu.hpp"
#include "protocol/function_code.hpp"

namespace mblab::server {

namespace {

constexpr auto use_tuple = asio::experimental::as_tuple(asio::use_awaitable);
// [SER] 2.5.2.1: an ASCII frame may pause up to 1 s between characters.
constexpr std::chrono::seconds kAsciiCharTimeout{1};

template <class Stream>
constexpr bool kIsSerialPort = std::is_same_v<Stream, asio::serial_port>;

}  // namespace

SerialLineHooks device_line_hooks(device::ReferenceDevice& device) {
    SerialLineHooks hooks;
    hooks.on_frame_error = [&device](LineError error) {
        if (error == LineError::ShortFrame) {
            device.count_short_frame();
        } else if (error == LineError::Checksum) {
            device.count_crc_error();
        }
    };
    hooks.on_overrun = [&device] { device.count_overrun(); };
    hooks.on_parity_error = [&device] { device.count_parity_error(); };
    hooks.ascii_delimiter = [&device](std::uint8_t unit) { return device.ascii_delimiter(unit); };
    return hooks;
}

std::string line_failure_text(const asio::error_code& ec) {
    if (ec == asio::error::eof || ec == std::errc::io_error) return "the line hung up";
    return ec.message();
}

LineSetup serial_line_setup(const transport::SerialUrl& url, SerialLineHooks hooks) {
    LineSetup setup;
    setup.hooks = std::move(hooks);
    if (url.kind == transport::SerialUrl::Kind::Ascii) {
        setup.framing = LineFraming::Ascii;
        setup.timing.silence = kAsciiCharTimeout;
        return setup;
    }
    const auto times = transport::rtu_char_times(url.line.baud);
    setup.framing = LineFraming::Rtu;
    setup.timing.silence = times.t35;
    if (url.strict_timing) setup.timing.char_gap = times.t15;
    setup.turnaround = times.t35;
    return setup;
}

template <class Stream>
LineSession<Stream>::LineSession(Stream stream, std::shared_ptr<ServerCore> core, LineSetup setup)
    : stream_(std::move(stream)),
      core_(std::move(core)),
      setup_(std::move(setup)),
      receiver_(setup_.framing, setup_.timing, protocol::Direction::Request, setup_.unknown_length),
      watchdog_timer_(stream_.get_executor()),
      delay_timer_(stream_.get_executor()),
      last_activity_(LineClock::now()) {
    if constexpr (kIsSerialPort<Stream>) faults_.emplace(stream_.native_handle());
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
    auto executor = stream_.get_executor();
    asio::co_spawn(executor, read_loop(this->shared_from_this()), asio::detached);
    asio::co_spawn(executor, watchdog_loop(this->shared_from_this()), asio::detached);
}

template <class Stream>
transport::Standing LineSession<Stream>::standing(LineClock::time_point now) const {
    using transport::Standing;
    // Not reading: answering a request, which is never the client's delay.
    if (closed_ || !reading_) return Standing::Busy;
    // Waiting for a request's first byte: nothing received to lose, nothing owed.
    if (!receiver_.has_partial()) return Standing::Idle;
    // Bytes without a whole request for long: a client that trickles holds the place unused.
    return now - last_activity_ >= core_->options.partial_frame_timeout ? Standing::Stalled
                                                                        : Standing::Busy;
}

template <class Stream>
void LineSession<Stream>::close() {
    if (closed_) return;
    closed_ = true;
    asio::error_code ignored;
    stream_.close(ignored);
    // Its place is free now, not once its coroutines have ended.
    leave_table();
    watchdog_timer_.cancel();
    delay_timer_.cancel();
}

template <class Stream>
void LineSession<Stream>::fail(const std::string& why) {
    if (!closed_ && setup_.on_failure) setup_.on_failure(why);
    close();
}

template <class Stream>
LineClock::time_point LineSession<Stream>::next_deadline() const {
    auto deadline = receiver_.deadline();
    if (setup_.idle_timeout.count() > 0) {
        deadline = std::min(deadline, last_activity_ + setup_.idle_timeout);
    }
    if (frame_open_) deadline = std::min(deadline, frame_started_ + core_->options.frame_limit);
    return deadline;
}

template <class Stream>
void LineSession<Stream>::count_line_faults() {
    if (!faults_) return;
    const auto faults = faults_->poll();
    for (std::uint32_t i = 0; i < faults.overruns && setup_.hooks.on_overrun; ++i)
        setup_.hooks.on_overrun();
    for (std::uint32_t i = 0; i < faults.parity_errors && setup_.hooks.on_parity_error; ++i)
        setup_.hooks.on_parity_error();
}

template <class Stream>
asio::awaitable<void> LineSession<Stream>::read_loop(Self /*self*/) {
    while (!closed_) {
        auto now = LineClock::now();
        if (now >= receiver_.deadline()) {
            const LineEvent event = receiver_.on_timeout(now);
            co_await handle(event);
            continue;
        }
        if (setup_.idle_timeout.count() > 0 && now >= last_activity_ + setup_.idle_timeout) {
            ServerStats::bump(core_->stats.closed_idle);
            close();
            break;
        }
        if (frame_open_ && now >= frame_started_ + core_->options.frame_limit) {
            // A client that trickles a frame: the rest of it would be read out of step.
            ServerStats::bump(core_->stats.closed_slow_frame);
            close();
            break;
        }
        reading_ = true;
        watchdog_timer_.cancel();  // rearm it for the deadline of this read
        auto [ec, size] = co_await stream_.async_read_some(asio::buffer(input_), use_tuple);
        reading_ = false;
        if (closed_) break;
        if (ec == asio::error::operation_aborted) continue;  // a deadline passed
        if (ec == asio::error::eof && !kIsSerialPort<Stream>) {
            // The peer finished sending: what it left unfinished can no longer complete.
            receiver_.reset();
            close();
            break;
        }
        if (ec) {
            fail(line_failure_text(ec));
            break;
        }
        count_line_faults();
        receiver_.receive(std::span<const std::uint8_t>(input_.data(), size), LineClock::now());
        for (LineEvent event = receiver_.next(); !event.empty() && !closed_;
             event = receiver_.next()) {
            co_await handle(event);
        }
        // Over TCP, a whole frame is bounded in time (ServerOptions::frame_limit); a serial line
        // paces its bytes itself, and a long frame at a low baud rate takes seconds.
        const bool open = !kIsSerialPort<Stream> && receiver_.has_partial();
        if (open && !frame_open_) frame_started_ = LineClock::now();
        frame_open_ = open;
    }
}

template <class Stream>
asio::awaitable<void> LineSession<Stream>::watchdog_loop(Self /*self*/) {
    while (!closed_) {
        // While the reader is busy it checks deadlines itself, and wakes this loop as it reads.
        watchdog_timer_.expires_at(reading_ ? next_deadline() : LineClock::time_point::max());
        co_await watchdog_timer_.async_wait(use_tuple);
        if (closed_) break;
        if (reading_ && LineClock::now() >= next_deadline()) {
            // Cancelling a read that already took bytes still delivers them.
            asio::error_code ignored;
            stream_.cancel(ignored);
            reading_ = false;
        }
    }
}

template <class Stream>
asio::awaitable<void> LineSession<Stream>::handle(const LineEvent& event) {
    if (event.is_error()) {
        ServerStats::bump(core_->stats.frames_dropped);
        if (event.error != LineError::None && setup_.hooks.on_frame_error) {
            setup_.hooks.on_frame_error(event.error);
        }
        co_return;
    }
    if (!event.is_frame()) co_return;
    const auto received_at = LineClock::now();
    last_activity_ = received_at;
    ServerStats::bump(core_->stats.requests);
    const std::uint8_t unit = event.frame.header.unit;
    const auto reply = core_->handler.handle({unit, device::Link::Serial}, event.frame.pdu,
                                             std::span(response_).first(protocol::limits::kMaxPdu));
    switch (reply.action) {
        case device::ReplyAction::NoAnswer:
            co_return;
        case device::ReplyAction::Close:
            // A serial line cannot be hung up on; a TCP connection can.
            if constexpr (!kIsSerialPort<Stream>) close();
            co_return;
        case device::ReplyAction::Answer:
            break;
    }
    const auto ready_at =
        std::max(received_at + reply.delay, receiver_.last_byte_time() + setup_.turnaround);
    co_await answer(unit, std::min(reply.size, protocol::limits::kMaxPdu), ready_at);
}

template <class Stream>
asio::awaitable<void> LineSession<Stream>::answer(std::uint8_t unit, std::size_t pdu_size,
                                                  LineClock::time_point ready_at) {
    const auto pdu = std::span<const std::uint8_t>(response_.data(), pdu_size);
    if (pdu_size > 0 && (pdu.front() & protocol::kExceptionBit)) {
        ServerStats::bump(core_->stats.exceptions);
    }
    const std::size_t size =
        protocol::write_adu({setup_.framing, unit}, pdu, output_, receiver_.ascii_delimiter());
    // FC 08 sub 03 changes the ASCII delimiter for the frames after its own answer.
    if (setup_.framing == LineFraming::Ascii && setup_.hooks.ascii_delimiter) {
        receiver_.set_ascii_delimiter(setup_.hooks.ascii_delimiter(unit));
    }
    if (LineClock::now() < ready_at) {
        delay_timer_.expires_at(ready_at);
        co_await delay_timer_.async_wait(use_tuple);
        if (closed_) co_return;
    }
    auto [ec, written] =
        co_await asio::async_write(stream_, asio::buffer(output_.data(), size), use_tuple);
    (void)written;
    if (ec) {
        fail(kIsSerialPort<Stream> ? line_failure_text(ec) : ec.message());
        co_return;
    }
    last_activity_ = LineClock::now();
}

template class LineSession<asio::serial_port>;
template class LineSession<asio::ip::tcp::socket>;

}  // namespace mblab::server
