#pragma once

#include <string>

#include "transport/channel.hpp"

namespace mblab::transport {

// A connected stream socket. It owns the descriptor and closes it; every call is non-blocking
// (MSG_DONTWAIT), whatever the descriptor's own mode, and never raises SIGPIPE.
class SocketChannel final : public Channel {
  public:
    explicit SocketChannel(int fd) : fd_(fd) {}
    ~SocketChannel() override { close(); }
    SocketChannel(const SocketChannel&) = delete;
    SocketChannel& operator=(const SocketChannel&) = delete;

    int fd() const { return fd_; }

    Io read(std::span<std::uint8_t> out) override;
    Io writev(std::span<const iovec> buffers) override;
    bool input_may_remain() const override { return read_filled_; }
    void shutdown_write() override;
    void close() override;
    PeerIdentity peer() const override;
    const std::string& error() const override { return error_; }

  private:
    int fd_ = -1;
    bool read_filled_ = false;
    std::string error_;  // always "": errno says why a socket call failed
};

}  // namespace mblab::transport
