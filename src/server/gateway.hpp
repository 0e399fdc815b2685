#pragma once

#include <array>
#include <asio/io_context.hpp>
#include <asio/serial_port.hpp>
#include <atomic>
#include <bitset>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "device/request_handler.hpp"
#include "protocol/limits.hpp"
#include "protocol/result.hpp"
#include "server/serial_line_receiver.hpp"
#include "transport/serial_master.hpp"
#include "transport/serial_url.hpp"

// A Modbus/TCP to serial gateway as a RequestHandler: put it behind a TcpServer and each
// request whose unit id is routed to the line goes out as an RTU or ASCII frame with that
// address; the device's answer comes back as the TCP answer.
//   - a unit id not routed to the line: exception 0A (gateway path unavailable);
//   - no valid answer within the line's response timeout: exception 0B (target failed to
//     respond); a routed unit 0 is sent as a broadcast and not answered.
// One request at a time is on the line, and t3.5 of silence separates RTU frames.
//
// A request for the line is queued for the gateway's own thread, the only one that uses the line,
// which answers it when the line has: handle_or_defer(), which the TCP server uses, does not
// wait, so one silent device never stalls the server's other connections (nor requests the
// gateway answers itself, like 0A); handle() waits for the answer, up to the response timeout.
namespace mblab::server {

struct LineSetup;

struct GatewayStats {
    using Counter = std::atomic<std::uint64_t>;
    Counter forwarded{0};    // requests sent on the line
    Counter answered{0};     // answers passed back
    Counter timeouts{0};     // answered 0B
    Counter unrouted{0};     // answered 0A: unit not routed, or the line failed
    Counter line_errors{0};  // bad frames and stray answers seen while waiting
};

class SerialGateway final : public device::DeferringHandler {
  public:
    // Opens the line at `url` (rtu:// or ascii://; its timeout= and units= apply).
    static protocol::Result<std::unique_ptr<SerialGateway>, std::string> open(
        const transport::SerialUrl& url);

    std::optional<device::Reply> handle_or_defer(const device::RequestContext& context,
                                                 std::span<const std::uint8_t> request,
                                                 std::span<std::uint8_t> response,
                                                 device::Deferral& deferral) override;

    // Ends the gateway's thread after the transaction on the line; requests still queued are
    // answered 0A. Called by the destructor; call it earlier when the server that gets the
    // answers goes first.
    void stop();
    ~SerialGateway() override;

    const GatewayStats& stats() const { return stats_; }

  private:
    struct Job {
        std::uint8_t unit = 0;
        std::vector<std::uint8_t> request;
        device::DeferredDone done;
    };

    SerialGateway(const transport::SerialUrl& url, const LineSetup& setup);
    // The request for the line, or the gateway's own answer (0A, nothing for an empty PDU).
    std::optional<device::Reply> answer_here(const device::RequestContext& context,
                                             std::span<const std::uint8_t> request,
                                             std::span<std::uint8_t> response);
    void work();

    device::Reply forward(std::uint8_t unit, std::span<const std::uint8_t> request,
                          std::span<std::uint8_t> response);
    bool send_frame(std::uint8_t unit, std::span<const std::uint8_t> request);
    // The device's answer PDU size in `response`, 0 when none came in time, -1 on a line error.
    long await_answer(std::span<std::uint8_t> response);
    static device::Reply exception(std::uint8_t function, std::uint8_t code,
                                   std::span<std::uint8_t> response);
    // Exception 0A, counted: no route to the unit, the line failed, or the gateway is stopping.
    device::Reply path_unavailable(std::uint8_t function, std::span<std::uint8_t> response);

    asio::io_context io_;  // owns the port; never run, the gateway's I/O is blocking
    asio::serial_port port_;
    LineFraming framing_;
    SerialLineReceiver receiver_;
    transport::SerialMaster master_;
    std::bitset<256> units_;
    std::chrono::milliseconds response_timeout_;  // also bounds writing a request
    GatewayStats stats_;

    std::mutex jobs_mutex_;
    std::condition_variable jobs_ready_;
    std::deque<Job> jobs_;
    bool stopping_ = false;
    std::thread worker_;  // started by the first deferred request
    std::array<std::uint8_t, protocol::limits::kMaxAsciiChars> frame_{};
    std::array<std::uint8_t, 512> input_{};
};

inline protocol::Result<std::unique_ptr<SerialGateway>, std::string> make_gateway(
    const transport::SerialUrl& url) {
    return SerialGateway::open(url);
}

}  // namespace mblab::server
