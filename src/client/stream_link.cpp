#include "client/stream_link.hpp"

#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <asio/connect.hpp>
#include <cerrno>
#include <cstring>
#include <thread>

#include "transport/serial_port.hpp"

namespace mblab::client {

namespace {

using Clock = std::chrono::steady_clock;
using std::chrono::milliseconds;

// USB serial adapters hand bytes over in bursts up to 16 ms apart: a shorter silence would cut
// their frames in pieces. Only frames whose layout does not give their length wait for it.
constexpr milliseconds kMinSerialSilence{20};
// RTU over TCP has no silence; a frame the CRC has not ended by then is given up.
constexpr milliseconds kTcpSilence{200};
// [SER 2.5.2.1]: the ASCII inter-character timeout.
constexpr milliseconds kAsciiSilence{1000};

std::string lowercase_first(std::string text) {
    if (!text.empty())
        text[0] = static_cast<char>(std::tolower(static_cast<unsigned char>(text[0])));
    return text;
}

int poll_ms(Clock::duration wait) {
    const auto ms = std::chrono::ceil<milliseconds>(std::max(wait, Clock::duration::zero()));
    return static_cast<int>(ms.count());
}

}  // namespace

StreamLink::StreamLink(std::string name, std::unique_ptr<asio::io_context> io,
                       std::unique_ptr<Port> port, const protocol::FramerOptions& framing,
                       std::chrono::microseconds silence, std::chrono::microseconds inter_frame,
                       LinkObserver* observer)
    : name_(std::move(name)),
      framing_(framing.framing),
      io_(std::move(io)),
      port_(std::move(port)),
      reader_(framing),
      silence_(silence),
      master_({.inter_frame = inter_frame}),
      observer_(observer) {
    fd_ = std::visit([](auto& p) { return static_cast<int>(p.native_handle()); }, *port_);
}

StreamLink::~StreamLink() {
    close();
}

void StreamLink::close() {
    port_.reset();  // closes the descriptor
    fd_ = -1;
    reader_.reset();
}

protocol::Result<std::unique_ptr<Link>, LinkError> StreamLink::open_serial(
    const transport::SerialUrl& url, std::string name, LinkObserver* observer) {
    auto io = std::make_unique<asio::io_context>();
    auto opened = transport::open_serial_port(io->get_executor(), url.line);
    if (!opened) return LinkError{opened.error()};
    auto port = std::make_unique<Port>(std::move(opened.value()));
    if (url.kind == transport::SerialUrl::Kind::Ascii) {
        auto link = std::unique_ptr<StreamLink>(
            new StreamLink(std::move(name), std::move(io), std::move(port),
                           {.framing = Framing::Ascii}, kAsciiSilence, {}, observer));
        if (url.paced) link->pace_ = transport::character_time(url.line);
        return std::unique_ptr<Link>(std::move(link));
    }
    const auto t35 = transport::rtu_char_times(url.line.baud).t35;
    auto link = std::unique_ptr<StreamLink>(
        new StreamLink(std::move(name), std::move(io), std::move(port),
                       {.framing = Framing::Rtu, .direction = protocol::Direction::Response},
                       std::max<std::chrono::microseconds>(t35, kMinSerialSilence), t35, observer));
    if (url.paced) link->pace_ = transport::character_time(url.line);
    return std::unique_ptr<Link>(std::move(link));
}

protocol::Result<std::unique_ptr<Link>, LinkError> StreamLink::open_rtu_over_tcp(
    const asio::ip::tcp::endpoint& endpoint, std::string name, milliseconds timeout,
    LinkObserver* observer) {
    auto io = std::make_unique<asio::io_context>();
    asio::ip::tcp::socket socket(*io);
    asio::error_code result = asio::error::would_block;
    socket.async_connect(endpoint, [&result](const asio::error_code& error) { result = error; });
    io->run_for(timeout);
    if (result == asio::error::would_block) return LinkError{"connection timed out"};
    if (result) return LinkError{lowercase_first(result.message())};
    asio::error_code ignored;
    socket.set_option(asio::ip::tcp::no_delay(true), ignored);
    return std::unique_ptr<Link>(
        new StreamLink(std::move(name), std::move(io), std::make_unique<Port>(std::move(socket)),
                       {.framing = Framing::Rtu,
                        .direction = protocol::Direction::Response,
                        .unknown_length = protocol::RtuFramer::UnknownLength::EndOnCrcMatch},
                       kTcpSilence, {}, observer));
}

bool StreamLink::send(std::span<const std::uint8_t> adu, LinkError& error) {
    if (Clock::now() < master_.line_free_at())
        std::this_thread::sleep_until(master_.line_free_at());
    if (observer_ != nullptr) observer_->on_sent(adu);
    if (pace_.count() <= 0) return write_all(adu, error);
    // A UART puts one character on the line per character time, and the far end has it once
    // its stop bit is in: character i is written at start + (i + 1) character times. A late
    // wake-up (a busy machine) writes every character due by then at once, so that a delay
    // never grows into a silence that would cut the frame.
    const auto start = Clock::now();
    std::size_t done = 0;
    while (done < adu.size()) {
        std::this_thread::sleep_until(start + pace_ * static_cast<long>(done + 1));
        const auto due = static_cast<std::size_t>((Clock::now() - start) / pace_);
        const std::size_t count = std::clamp(due, done + 1, adu.size()) - done;
        if (!write_all(adu.subspan(done, count), error)) return false;
        done += count;
    }
    return true;
}

bool StreamLink::write_all(std::span<const std::uint8_t> adu, LinkError& error) {
    while (!adu.empty()) {
        if (fd_ < 0) {
            error.message = "connection closed";
            return false;
        }
        const ssize_t written = ::write(fd_, adu.data(), adu.size());
        if (written > 0) {
            adu = adu.subspan(static_cast<std::size_t>(written));
            continue;
        }
        if (written < 0 && (errno == EAGAIN || errno == EINTR)) {
            pollfd ready{fd_, POLLOUT, 0};
            ::poll(&ready, 1, 1000);
            continue;
        }
        error.message = lowercase_first(std::strerror(errno));
        close();
        return false;
    }
    return true;
}

Received StreamLink::receive_frame(milliseconds timeout) {
    Received received = read_frame(timeout);
    if (observer_ != nullptr && !received.bytes.empty()) observer_->on_received(received.bytes);
    return received;
}

Received StreamLink::read_frame(milliseconds timeout) {
    const auto deadline = Clock::now() + timeout;
    // The longest silence between two reads that both brought bytes of the frame (the line's
    // timing as seen here: a pty does not pace bytes, an adapter adds its latency timer).
    Clock::time_point last_bytes{};
    Clock::duration largest_gap{};
    const auto timed = [&](Received frame) {
        frame.largest_gap = std::chrono::duration_cast<std::chrono::microseconds>(largest_gap);
        return frame;
    };
    while (true) {
        if (auto frame = reader_.next()) return timed(std::move(*frame));
        if (fd_ < 0) return reader_.take(ReceiveStatus::Closed, "connection closed");
        const auto left = deadline - Clock::now();
        const bool held = reader_.has_partial();
        const auto wait = held ? std::min<Clock::duration>(left, silence_) : left;
        pollfd ready{fd_, POLLIN, 0};
        const int polled = ::poll(&ready, 1, poll_ms(wait));
        if (polled < 0 && errno == EINTR) continue;
        if (polled > 0) {
            std::uint8_t chunk[512];
            const ssize_t got = ::read(fd_, chunk, sizeof chunk);
            if (got > 0) {
                const auto now = Clock::now();
                if (reader_.has_partial() && last_bytes != Clock::time_point{})
                    largest_gap = std::max(largest_gap, now - last_bytes);
                last_bytes = now;
                master_.heard(now);
                reader_.add({chunk, static_cast<std::size_t>(got)});
                continue;
            }
            if (got < 0 && (errno == EAGAIN || errno == EINTR)) continue;
            const std::string why =
                got == 0 ? "connection closed by peer" : lowercase_first(std::strerror(errno));
            Received out = reader_.take(ReceiveStatus::Closed, why);
            close();
            return out;
        }
        if (held) {
            if (auto done = reader_.on_silence()) return timed(std::move(*done));
        }
        if (Clock::now() >= deadline) return reader_.take(ReceiveStatus::Timeout);
    }
}

}  // namespace mblab::client
