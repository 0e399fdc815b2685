// transport::SocketChannel on a real socket pair: what a read says about the bytes it left.
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <cstdint>

#include "transport/socket_channel.hpp"

namespace {

using mblab::transport::Io;
using mblab::transport::SocketChannel;

// An owner woken only by new input must read again after a read that filled its room, and need
// not after one that did not: that is all the channel can know without another recv().
TEST(SocketChannel, SaysInputMayRemainOnlyAfterAReadThatFilledItsRoom) {
    int fds[2];
    ASSERT_EQ(::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fds), 0);
    SocketChannel ours(fds[0]);
    const char ten[] = "0123456789";
    ASSERT_EQ(::write(fds[1], ten, 10), 10);

    std::array<std::uint8_t, 4> small{};
    auto io = ours.read(small);
    ASSERT_EQ(io.status, Io::Status::Done);
    EXPECT_EQ(io.bytes, 4U);
    EXPECT_TRUE(ours.input_may_remain()) << "4 of 10 bytes read";

    std::array<std::uint8_t, 64> large{};
    io = ours.read(large);
    ASSERT_EQ(io.status, Io::Status::Done);
    EXPECT_EQ(io.bytes, 6U);
    EXPECT_FALSE(ours.input_may_remain()) << "the rest read, with room to spare";

    io = ours.read(large);
    EXPECT_EQ(io.status, Io::Status::WouldBlock);
    EXPECT_FALSE(ours.input_may_remain());
    ::close(fds[1]);
}

}  // namespace
