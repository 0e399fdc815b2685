// The byte queues under a TlsChannel, seen as OpenSSL sees them (BIO calls) and as the channel's
// owner does (bytes, drop).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "security/queue_bio.hpp"

namespace mblab::test {
namespace {

using security::ByteQueue;

std::vector<std::uint8_t> bytes(std::string_view text) {
    return {text.begin(), text.end()};
}

std::string text_of(std::span<const std::uint8_t> span) {
    return {span.begin(), span.end()};
}

struct Bio {
    explicit Bio(ByteQueue& queue) : bio(security::new_queue_bio(queue)) {}
    ~Bio() { BIO_free(bio); }
    BIO* bio;
};

TEST(ByteQueue, TakesFromTheFrontInTheOrderBytesCame) {
    ByteQueue queue;
    queue.append(bytes("abcdef"));
    std::vector<std::uint8_t> out(4);
    EXPECT_EQ(queue.take(out), 4u);
    EXPECT_EQ(text_of(out), "abcd");
    queue.append(bytes("gh"));  // after a partial take: the untaken bytes stay first
    EXPECT_EQ(text_of(queue.bytes()), "efgh");
    queue.drop(3);
    EXPECT_EQ(text_of(queue.bytes()), "h");
    queue.drop(10);  // more than it holds: empty, not beyond
    EXPECT_TRUE(queue.empty());
    EXPECT_EQ(queue.take(out), 0u);
    queue.append(bytes("i"));
    EXPECT_EQ(text_of(queue.bytes()), "i");
}

TEST(QueueBio, WritesAppendAndReadsTakeWhatCame) {
    ByteQueue queue;
    Bio b(queue);
    ASSERT_NE(b.bio, nullptr);
    EXPECT_EQ(BIO_write(b.bio, "hello", 5), 5);
    EXPECT_EQ(BIO_write(b.bio, " you", 4), 4);
    EXPECT_EQ(text_of(queue.bytes()), "hello you");
    EXPECT_EQ(BIO_ctrl_pending(b.bio), 9u);
    EXPECT_EQ(BIO_ctrl_wpending(b.bio), 9u);
    EXPECT_EQ(BIO_flush(b.bio), 1);
    char out[6] = {};
    EXPECT_EQ(BIO_read(b.bio, out, 5), 5);
    EXPECT_EQ(std::string(out, 5), "hello");
    EXPECT_EQ(queue.size(), 4u);
}

// TLS waits for more when the queue is empty: -1 and "retry, read", never end of file.
TEST(QueueBio, AnEmptyQueueSaysRetryNotEnd) {
    ByteQueue queue;
    Bio b(queue);
    char out[4];
    EXPECT_EQ(BIO_read(b.bio, out, sizeof out), -1);
    EXPECT_TRUE(BIO_should_retry(b.bio));
    EXPECT_TRUE(BIO_should_read(b.bio));
    EXPECT_EQ(BIO_eof(b.bio), 0);
    queue.append(bytes("ab"));
    EXPECT_EQ(BIO_read(b.bio, out, sizeof out), 2);
    EXPECT_FALSE(BIO_should_retry(b.bio));
}

}  // namespace
}  // namespace mblab::test
