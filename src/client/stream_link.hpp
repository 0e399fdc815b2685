#pragma once

#include <asio/io_context.hpp>
#include <asio/ip/tcp.hpp>
#include <asio/serial_port.hpp>
#include <chrono>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "client/frame_reader.hpp"
#include "client/link.hpp"
#include "protocol/result.hpp"
#include "transport/serial_master.hpp"
#include "transport/serial_url.hpp"

// Links whose frames are cut by a serial framer rather than by a length header: RTU and ASCII on
// a serial line, and RTU over TCP. Blocking, like RawLink: every wait is a poll() with a deadline
// on the port's descriptor; Asio only opens the port (its termios setup) or connects the socket.
// A request waits for the line to be free as transport::SerialMaster, the gateway's master too,
// says (the inter-frame silence after what was heard). Every frame is handed up, from whatever
// address: the tester judges an answer a plain master would discard [SER 2.4.1].
namespace mblab::client {

class StreamLink final : public Link {
  public:
    // rtu://, ascii://: the serial line the URL names.
    // `observer` is told of every write and of every frame (or garbled bytes) read.
    static protocol::Result<std::unique_ptr<Link>, LinkError> open_serial(
        const transport::SerialUrl& url, std::string name, LinkObserver* observer = nullptr);
    // rtu+tcp://: RTU frames over a TCP connection.
    static protocol::Result<std::unique_ptr<Link>, LinkError> open_rtu_over_tcp(
        const asio::ip::tcp::endpoint& endpoint, std::string name,
        std::chrono::milliseconds timeout, LinkObserver* observer = nullptr);
    ~StreamLink() override;

    Framing framing() const override { return framing_; }
    const std::string& name() const override { return name_; }
    bool is_open() const override { return fd_ >= 0; }
    bool send(std::span<const std::uint8_t> adu, LinkError& error) override;
    Received receive_frame(std::chrono::milliseconds timeout) override;
    // On a line anything the device sends arrives as a frame or a framing error.
    Received receive_any(std::chrono::milliseconds timeout) override {
        return receive_frame(timeout);
    }
    void close() override;

  private:
    using Port = std::variant<asio::serial_port, asio::ip::tcp::socket>;

    StreamLink(std::string name, std::unique_ptr<asio::io_context> io, std::unique_ptr<Port> port,
               const protocol::FramerOptions& framing, std::chrono::microseconds silence,
               std::chrono::microseconds inter_frame, LinkObserver* observer);
    // receive_frame() without telling the observer.
    Received read_frame(std::chrono::milliseconds timeout);
    bool write_all(std::span<const std::uint8_t> bytes, LinkError& error);

    std::string name_;
    Framing framing_;
    std::unique_ptr<asio::io_context> io_;
    std::unique_ptr<Port> port_;
    FrameReader reader_;
    // Quiet time that ends a frame whose layout does not say its length (t3.5 on RTU lines).
    std::chrono::microseconds silence_;
    transport::SerialMaster master_;
    int fd_ = -1;
    LinkObserver* observer_ = nullptr;
    // A character time when the URL says pace=1: requests go out at the baud rate.
    std::chrono::nanoseconds pace_{0};
};

}  // namespace mblab::client
