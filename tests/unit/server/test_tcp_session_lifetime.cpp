// The driver against a real socket where the sans-I/O traces cannot reach: what keeps an open
// TcpSession alive.
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <asio/io_context.hpp>
#include <asio/ip/address_v4.hpp>
#include <cstring>
#include <thread>

#include "server/tcp_server.hpp"
#include "support/hex.hpp"

namespace mblab::test {
namespace {

class Echo final : public device::RequestHandler {
  public:
    device::Reply handle(const device::RequestContext&, std::span<const std::uint8_t> request,
                         std::span<std::uint8_t> response) override {
        std::memcpy(response.data(), request.data(), request.size());
        return {device::ReplyAction::Answer, request.size(), {}};
    }
};

// With --idle-timeout 0 nothing is due, and the session's pending timer wait is still what holds
// it: without one it was destroyed as soon as it started, and the client was reset.
TEST(TcpSessionLifetime, SessionWithoutIdleTimeoutStaysOpenAndAnswers) {
    asio::io_context io;
    Echo echo;
    server::ServerOptions options;
    options.idle_timeout = std::chrono::milliseconds(0);
    server::TcpServer server(io, echo, options);
    const auto port = server.start({asio::ip::address_v4::loopback(), 0});
    ASSERT_TRUE(port);
    std::thread runner([&io] { io.run_for(std::chrono::seconds(5)); });

    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(port.value());
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ASSERT_EQ(::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address), 0);
    timeval wait{2, 0};
    ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &wait, sizeof wait);
    const auto request = hex("00 01 00 00 00 03 01 08 00");
    std::array<std::uint8_t, 64> answer{};
    for (int i = 0; i < 2; ++i) {
        ASSERT_EQ(::send(fd, request.data(), request.size(), 0),
                  static_cast<ssize_t>(request.size()));
        const auto got = ::recv(fd, answer.data(), answer.size(), 0);
        ASSERT_GT(got, 0) << std::strerror(errno);
        EXPECT_EQ(to_hex(std::span(answer).first(static_cast<std::size_t>(got))),
                  "00 01 00 00 00 03 01 08 00");
    }
    ::close(fd);
    asio::post(io, [&] { server.stop(); });
    io.stop();
    runner.join();
}

}  // namespace
}  // namespace mblab::test
