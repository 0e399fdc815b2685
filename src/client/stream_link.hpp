#pragma once

#include <asio/io_context.hpp>
#include <asio/ip/tcp.hpp>
#include <asio/serial_port.hpp>
#include <chrono>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "client/link.hpp"
#include "protocol/frame_event.hpp"
#include "protocol/result.hpp"
#include "transport/serial_url.hpp"

// Links whose frames are cut by a serial framer rather than by a length header: RTU and ASCII on
// a serial line, and RTU over TCP. Blocking, like RawLink: every wait is a poll() with a deadline
// on the port's descriptor; Asio only opens the port (its termios setup) or connects the socket.
namespace mblab::client {

// One of the protocol's serial framers (RtuFramer, AsciiFramer) behind one interface.
class FrameCutter {
  public:
    virtual ~FrameCutter() = default;
    virtual protocol::FrameEvent feed(std::span<const std::uint8_t> input,
                                      std::size_t& consumed) = 0;
    virtual protocol::FrameEvent on_silence() = 0;
    virtual bool has_partial() const = 0;
    virtual void reset() = 0;
};

class StreamLink final : public Link {
  public:
    // rtu://, ascii://: the serial line the URL names.
    static protocol::Result<std::unique_ptr<Link>, LinkError> open_serial(
        const transport::SerialUrl& url, std::string name);
    // rtu+tcp://: RTU frames over a TCP connection.
    static protocol::Result<std::unique_ptr<Link>, LinkError> open_rtu_over_tcp(
        const asio::ip::tcp::endpoint& endpoint, std::string name,
        std::chrono::milliseconds timeout);
    ~StreamLink() override;

    Framing framing() const override { return framing_; }
    const std::string& name() const override { return name_; }
    bool is_open() const override { return fd_ >= 0; }
    bool send(std::span<const std::uint8_t> adu, LinkError& error) override;
    Received receive_frame(std::chrono::milliseconds timeout) override;
    void close() override;

  private:
    using Port = std::variant<asio::serial_port, asio::ip::tcp::socket>;

    StreamLink(std::string name, Framing framing, std::unique_ptr<asio::io_context> io,
               std::unique_ptr<Port> port, std::unique_ptr<FrameCutter> cutter,
               std::chrono::microseconds silence);
    // A whole frame or a framing error from the bytes held, if there is one.
    std::optional<Received> cut(const protocol::FrameEvent& event);
    Received take(ReceiveStatus status, std::string detail);

    std::string name_;
    Framing framing_;
    std::unique_ptr<asio::io_context> io_;
    std::unique_ptr<Port> port_;
    std::unique_ptr<FrameCutter> cutter_;
    // Quiet time that ends a frame whose layout does not say its length (t3.5 on RTU lines).
    std::chrono::microseconds silence_;
    int fd_ = -1;
    std::vector<std::uint8_t> pending_;  // read but not yet given to the cutter
    std::vector<std::uint8_t> partial_;  // given to the cutter, frame not finished
};

}  // namespace mblab::client
