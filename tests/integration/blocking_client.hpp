#pragma once

#include <chrono>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

// A plain POSIX TCP client for server tests: every wait has a timeout, so a server that does
// not answer fails the test instead of hanging it.
namespace mblab::test {

using namespace std::chrono_literals;

class BlockingClient {
  public:
    BlockingClient() = default;
    // Connects to 127.0.0.1:port; connected() tells whether it worked. A receive_buffer (bytes)
    // shrinks the socket's, and with it the window the server may fill before the client reads.
    explicit BlockingClient(std::uint16_t port, int receive_buffer = 0);
    ~BlockingClient();
    BlockingClient(BlockingClient&& other) noexcept;
    BlockingClient& operator=(BlockingClient&& other) noexcept;

    bool connected() const { return fd_ >= 0; }
    bool send(std::span<const std::uint8_t> bytes);
    bool send_hex(std::string_view hex_bytes);
    // Half-closes: the server sees end of stream.
    void shutdown_send();

    // Reads up to `count` bytes, waiting at most `timeout` in all; returns what arrived.
    std::vector<std::uint8_t> read(std::size_t count, std::chrono::milliseconds timeout = 5s);
    // One MBAP ADU (header, then as many bytes as its length says), as "00 01 ..." hex; the
    // bytes that arrived when the time ran out or the connection closed.
    std::string read_adu(std::chrono::milliseconds timeout = 5s);
    // Sends a request (hex) and reads one answer (hex).
    std::string transact(std::string_view request_hex, std::chrono::milliseconds timeout = 5s);
    // True when the server closed the connection (EOF or reset) within `timeout`; bytes that
    // arrive first are discarded.
    bool closed_by_peer(std::chrono::milliseconds timeout = 5s);
    // How the last read that found the connection's end failed: errno (ECONNRESET for a reset),
    // or 0 for an orderly end (the server's FIN) and while no read has found one.
    int end_error() const { return end_error_; }

  private:
    // -1: error or EOF, 0: timeout, else bytes read.
    long read_some(std::uint8_t* out, std::size_t count, std::chrono::milliseconds timeout);

    int fd_ = -1;
    int end_error_ = 0;
};

}  // namespace mblab::test
