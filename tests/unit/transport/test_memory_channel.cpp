// The in-memory channel pair the driver tests run on: what a non-blocking socket pair would
// report, and the failures tests inject (short writes, a stalled reader, a reset, a close).
#include <gtest/gtest.h>

#include <array>
#include <cerrno>
#include <string>

#include "transport/memory_channel.hpp"

namespace mblab::test {
namespace {

using transport::Io;
using transport::MemoryPair;
using Status = Io::Status;

std::span<const std::uint8_t> bytes_of(const std::string& text) {
    return {reinterpret_cast<const std::uint8_t*>(text.data()), text.size()};
}

Io read_some(MemoryPair::End& end) {
    std::array<std::uint8_t, 4> buffer{};
    return end.read(buffer);
}

std::string read_text(MemoryPair::End& end) {
    std::array<std::uint8_t, 64> buffer{};
    const auto io = end.read(buffer);
    return io.status == Status::Done ? std::string(buffer.begin(), buffer.begin() + io.bytes) : "";
}

TEST(MemoryPair, WhatOneEndWritesTheOtherReadsInOrder) {
    MemoryPair pair;
    EXPECT_EQ(pair.client().write(bytes_of("abc")).bytes, 3U);
    const std::string more = "de";
    const std::string last = "f";
    const std::array<iovec, 2> gathered{iovec{const_cast<char*>(more.data()), more.size()},
                                        iovec{const_cast<char*>(last.data()), last.size()}};
    EXPECT_EQ(pair.client().writev(gathered).bytes, 3U);
    EXPECT_TRUE(pair.server().readable());
    EXPECT_EQ(read_text(pair.server()), "abcdef");
    EXPECT_FALSE(pair.server().readable());
    EXPECT_EQ(read_some(pair.server()).status, Status::WouldBlock);
}

TEST(MemoryPair, ShortWritesTakePartOfWhatIsGiven) {
    MemoryPair pair;
    pair.client().set_max_write(2);
    EXPECT_EQ(pair.client().write(bytes_of("abcde")).bytes, 2U);
    EXPECT_EQ(read_text(pair.server()), "ab");
}

TEST(MemoryPair, AReaderThatStallsFillsTheWindow) {
    MemoryPair pair;
    pair.server().set_window(4);
    EXPECT_EQ(pair.server().write(bytes_of("abcdef")).bytes, 4U);
    EXPECT_FALSE(pair.server().writable());
    EXPECT_EQ(pair.server().write(bytes_of("x")).status, Status::WouldBlock);
    EXPECT_EQ(read_text(pair.client()), "abcd");
    EXPECT_TRUE(pair.server().writable());
}

TEST(MemoryPair, CloseIsReadAsTheEndOfInputAfterTheBytesBeforeIt) {
    MemoryPair pair;
    pair.server().write(bytes_of("bye"));
    pair.server().close();
    EXPECT_EQ(pair.server().write(bytes_of("x")).status, Status::Failed);
    EXPECT_EQ(read_text(pair.client()), "bye");
    EXPECT_TRUE(pair.client().at_end_of_input());
    EXPECT_EQ(read_some(pair.client()).status, Status::EndOfInput);
}

TEST(MemoryPair, ResetFailsBothEndsAndLosesWhatWasInFlight) {
    MemoryPair pair;
    pair.client().write(bytes_of("lost"));
    pair.server().reset();
    const auto io = read_some(pair.server());
    EXPECT_EQ(io.status, Status::Failed);
    EXPECT_EQ(io.code, ECONNRESET);
    EXPECT_EQ(pair.client().write(bytes_of("x")).status, Status::Failed);
    EXPECT_TRUE(pair.client().readable());  // a readiness loop is told, and reads the failure
}

}  // namespace
}  // namespace mblab::test
