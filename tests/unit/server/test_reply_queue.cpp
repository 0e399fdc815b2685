#include <gtest/gtest.h>

#include <cstdint>

#include "server/reply_queue.hpp"

namespace mblab::server {
namespace {

// Issue 17 item 7: the whole ring was allocated at the first answer (11.7 KB by default, 1.16 MB
// with --max-outstanding 4096) although most clients have one request outstanding.
TEST(ReplyQueue, AllocatesNothingUntilTheFirstAnswerAndThenLittle) {
    ReplyQueue queue(4096 + 18);
    EXPECT_EQ(queue.allocated(), 0U);
    ASSERT_NE(queue.push_back(), nullptr);
    EXPECT_EQ(queue.allocated(), 2U);
    queue.pop_front(1);
    ASSERT_NE(queue.push_back(), nullptr);
    ASSERT_NE(queue.push_back(), nullptr);
    EXPECT_EQ(queue.allocated(), 2U);
}

TEST(ReplyQueue, GrowsByDoublingUpToItsCapacityAndKeepsTheOrder) {
    ReplyQueue queue(5);
    // Wrap the ring around before it grows: the head is not at slot 0.
    queue.push_back()->size = 100;
    queue.push_back()->size = 101;
    queue.pop_front(1);
    for (std::uint16_t size = 102; size <= 105; ++size) {
        auto* slot = queue.push_back();
        ASSERT_NE(slot, nullptr);
        slot->size = size;
    }
    EXPECT_EQ(queue.allocated(), 5U);
    EXPECT_EQ(queue.push_back(), nullptr);
    ASSERT_EQ(queue.size(), 5U);
    for (std::size_t i = 0; i < queue.size(); ++i)
        EXPECT_EQ(queue.at(i).size, 101 + i);
}

}  // namespace
}  // namespace mblab::server
