#include "server/gateway.hpp"

#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <thread>

#include "protocol/adu.hpp"
#include "protocol/exception_code.hpp"
#include "protocol/function_code.hpp"
#include "server/line_session_core.hpp"
#include "transport/serial_port.hpp"

namespace mblab::server {

namespace {

using protocol::ExceptionCode;

// Waits until `fd` is ready for `events` or `until` passes; true when ready.
bool wait_ready(int fd, short events, LineClock::time_point until) {
    for (;;) {
        const auto left = std::max(until - LineClock::now(), LineClock::duration::zero());
        const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(left).count();
        timespec timeout{static_cast<time_t>(ns / 1'000'000'000),
                         static_cast<long>(ns % 1'000'000'000)};
        pollfd entry{fd, events, 0};
        const int ready = ::ppoll(&entry, 1, &timeout, nullptr);
        if (ready > 0) return true;
        if (ready == 0) return false;
        if (errno != EINTR) return false;
    }
}

}  // namespace

SerialGateway::SerialGateway(const transport::SerialUrl& url, const LineSetup& setup)
    : port_(io_),
      framing_(setup.framing),
      receiver_(setup.framing, setup.timing, protocol::Direction::Response),
      // A broadcast's turnaround is the inter-frame silence: the devices that execute it do
      // not answer, so nothing on the line waits for them.
      master_({setup.turnaround, setup.turnaround, url.response_timeout}),
      units_(url.units),
      response_timeout_(url.response_timeout) {}

protocol::Result<std::unique_ptr<SerialGateway>, std::string> SerialGateway::open(
    const transport::SerialUrl& url) {
    if (url.kind == transport::SerialUrl::Kind::RtuOverTcp) {
        return std::string("a gateway needs a serial line (rtu:// or ascii://), not rtu+tcp://");
    }
    std::unique_ptr<SerialGateway> gateway(new SerialGateway(url, serial_line_setup(url, {})));
    auto port = transport::open_serial_port(gateway->io_.get_executor(), url.line);
    if (!port) return port.error();
    gateway->port_ = std::move(port.value());
    return gateway;
}

device::Reply SerialGateway::exception(std::uint8_t function, std::uint8_t code,
                                       std::span<std::uint8_t> response) {
    response[0] = static_cast<std::uint8_t>(function | protocol::kExceptionBit);
    response[1] = code;
    return {device::ReplyAction::Answer, 2, {}};
}

std::optional<device::Reply> SerialGateway::answer_here(const device::RequestContext& context,
                                                        std::span<const std::uint8_t> request,
                                                        std::span<std::uint8_t> response) {
    if (request.empty()) return device::Reply{device::ReplyAction::NoAnswer, 0, {}};
    if (!units_.test(context.unit)) {
        return path_unavailable(request[0], response);
    }
    return std::nullopt;
}

device::Reply SerialGateway::path_unavailable(std::uint8_t function,
                                              std::span<std::uint8_t> response) {
    ++stats_.unrouted;
    return exception(function, static_cast<std::uint8_t>(ExceptionCode::GatewayPathUnavailable),
                     response);
}

std::optional<device::Reply> SerialGateway::handle_or_defer(const device::RequestContext& context,
                                                            std::span<const std::uint8_t> request,
                                                            std::span<std::uint8_t> response,
                                                            device::Deferral& deferral) {
    if (auto here = answer_here(context, request, response)) return here;
    std::lock_guard lock(jobs_mutex_);
    if (stopping_) {
        return path_unavailable(request[0], response);
    }
    jobs_.push_back({context.unit, {request.begin(), request.end()}, deferral.take()});
    if (!worker_.joinable()) worker_ = std::thread([this] { work(); });
    jobs_ready_.notify_one();
    return std::nullopt;
}

void SerialGateway::work() {
    std::array<std::uint8_t, protocol::limits::kMaxPdu> response{};
    for (;;) {
        Job job;
        bool give_up = false;
        {
            std::unique_lock lock(jobs_mutex_);
            jobs_ready_.wait(lock, [this] { return stopping_ || !jobs_.empty(); });
            if (jobs_.empty()) return;
            job = std::move(jobs_.front());
            jobs_.pop_front();
            give_up = stopping_;
        }
        device::Reply reply;
        if (give_up) {
            reply = path_unavailable(job.request[0], response);
        } else {
            reply = forward(job.unit, job.request, response);
        }
        job.done(reply, std::span(response).first(std::min(reply.size, response.size())));
    }
}

void SerialGateway::stop() {
    std::thread worker;
    {
        std::lock_guard lock(jobs_mutex_);
        stopping_ = true;
        worker = std::move(worker_);  // handle_or_defer() starts it under this lock
    }
    jobs_ready_.notify_all();
    if (worker.joinable()) worker.join();
}

SerialGateway::~SerialGateway() {
    stop();
}

device::Reply SerialGateway::forward(std::uint8_t unit, std::span<const std::uint8_t> request,
                                     std::span<std::uint8_t> response) {
    const std::uint8_t function = request[0];
    // What came while no request waited is late or unasked, which the master discards: the
    // kernel's buffer drops it sooner.
    ::tcflush(port_.native_handle(), TCIFLUSH);
    receiver_.reset();
    std::this_thread::sleep_until(master_.line_free_at());
    if (!send_frame(unit, request)) return path_unavailable(function, response);
    ++stats_.forwarded;
    master_.request_sent(unit, function, LineClock::now());
    if (master_.state() != transport::SerialMaster::State::WaitingReply) {
        return {device::ReplyAction::NoAnswer, 0, {}};  // a broadcast
    }
    const long size = await_answer(response);
    if (size < 0) return path_unavailable(function, response);
    if (size == 0) {
        ++stats_.timeouts;
        return exception(function,
                         static_cast<std::uint8_t>(ExceptionCode::GatewayTargetFailedToRespond),
                         response);
    }
    ++stats_.answered;
    return {device::ReplyAction::Answer, static_cast<std::size_t>(size), {}};
}

bool SerialGateway::send_frame(std::uint8_t unit, std::span<const std::uint8_t> request) {
    const std::size_t size = protocol::write_adu({framing_, unit}, request, frame_);
    if (size == 0) return false;
    const int fd = port_.native_handle();
    const auto give_up = LineClock::now() + response_timeout_;
    for (std::size_t sent = 0; sent < size;) {
        const auto n = ::write(fd, frame_.data() + sent, size - sent);
        if (n > 0) {
            sent += static_cast<std::size_t>(n);
        } else if (n < 0 && errno != EAGAIN && errno != EINTR) {
            return false;
        } else if (!wait_ready(fd, POLLOUT, give_up)) {
            return false;
        }
    }
    // The response timeout runs from the end of the request on the wire.
    return ::tcdrain(fd) == 0 || errno == ENOTTY;
}

long SerialGateway::await_answer(std::span<std::uint8_t> response) {
    using Verdict = transport::SerialMaster::Verdict;
    const int fd = port_.native_handle();
    const auto take = [&](const LineEvent& event) -> long {
        if (event.is_error()) ++stats_.line_errors;
        if (!event.is_frame()) return 0;
        const auto pdu = event.frame.pdu;
        if (pdu.size() > response.size() ||
            master_.on_frame(event.frame.header.unit, pdu, LineClock::now()) != Verdict::Answer) {
            ++stats_.line_errors;
            return 0;
        }
        std::copy(pdu.begin(), pdu.end(), response.begin());
        return static_cast<long>(pdu.size());
    };
    for (;;) {
        auto now = LineClock::now();
        if (now >= receiver_.deadline()) {
            if (const long size = take(receiver_.on_timeout(now))) return size;
            continue;
        }
        if (master_.on_time(now) == transport::SerialMaster::Timeout::NoAnswer) return 0;
        if (!wait_ready(fd, POLLIN, std::min(master_.deadline(), receiver_.deadline()))) continue;
        const auto n = ::read(fd, input_.data(), input_.size());
        if (n < 0 && (errno == EAGAIN || errno == EINTR)) continue;
        if (n <= 0) return -1;
        now = LineClock::now();
        master_.heard(now);
        receiver_.receive(std::span<const std::uint8_t>(input_.data(), static_cast<std::size_t>(n)),
                          now);
        for (LineEvent event = receiver_.next(); !event.empty(); event = receiver_.next()) {
            if (const long size = take(event)) return size;
        }
    }
}

}  // namespace mblab::server
