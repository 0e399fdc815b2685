#include <gtest/gtest.h>
#include <sys/socket.h>
#include <unistd.h>

#include <asio/io_context.hpp>
#include <asio/post.hpp>
#include <asio/steady_timer.hpp>
#include <chrono>
#include <functional>
#include <memory>
#include <vector>

#include "transport/socket_poller.hpp"

namespace {

using mblab::transport::SocketPoller;

// A connected pair of stream sockets, closed at the end of the test.
struct SocketPair {
    int ours = -1;
    int theirs = -1;
    SocketPair() {
        int fds[2];
        EXPECT_EQ(::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fds), 0);
        ours = fds[0];
        theirs = fds[1];
    }
    ~SocketPair() {
        if (ours >= 0) ::close(ours);
        if (theirs >= 0) ::close(theirs);
    }
    void send_byte(char byte = 'x') const { ASSERT_EQ(::write(theirs, &byte, 1), 1); }
};

struct RecordingWatcher final : SocketPoller::Watcher {
    std::vector<std::uint32_t> events;
    std::function<void(std::uint32_t)> action;
    // What on_ready() answers: whether input may have been left unread.
    bool leaves_input = true;
    bool on_ready(std::uint32_t ready) override {
        events.push_back(ready);
        if (action) action(ready);
        return leaves_input;
    }
};

// A poller, a socket pair whose first end it may watch, and a watcher that records.
class SocketPollerTest : public ::testing::Test {
  protected:
    asio::io_context io;
    std::shared_ptr<SocketPoller> poller = SocketPoller::create(io.get_executor());
    SocketPair pair;
    std::shared_ptr<RecordingWatcher> watcher = std::make_shared<RecordingWatcher>();
};

char read_byte(int fd) {
    char byte = 0;
    EXPECT_EQ(::read(fd, &byte, 1), 1);
    return byte;
}

TEST_F(SocketPollerTest, ReportsInputUntilItIsRead) {
    // Level-triggered: unread input is reported again; the second time it is read and the
    // descriptor removed, which lets run() return.
    watcher->action = [&](std::uint32_t) {
        if (watcher->events.size() == 2) {
            EXPECT_EQ(read_byte(pair.ours), 'a');
            poller->remove(pair.ours);
        }
    };
    ASSERT_TRUE(poller->add(pair.ours, *watcher, EPOLLIN));
    pair.send_byte('a');
    io.run();
    ASSERT_EQ(watcher->events.size(), 2U);
    EXPECT_EQ(watcher->events[0] & EPOLLIN, static_cast<std::uint32_t>(EPOLLIN));
    EXPECT_EQ(poller->watched(), 0U);
}

TEST_F(SocketPollerTest, RunReturnsWhenNothingIsWatched) {
    ASSERT_TRUE(poller->add(pair.ours, *watcher, EPOLLIN));
    // No input ever comes: only the removal ends the wait.
    asio::post(io, [&] { poller->remove(pair.ours); });
    io.run();
    EXPECT_TRUE(watcher->events.empty());
}

TEST_F(SocketPollerTest, WatchesAgainAfterEverythingWasRemoved) {
    SocketPair& first = pair;
    SocketPair second;
    watcher->action = [&](std::uint32_t) {
        read_byte(second.ours);
        poller->remove(second.ours);
    };
    ASSERT_TRUE(poller->add(first.ours, *watcher, EPOLLIN));
    // The removal cancels the pending wait; the add that follows at once must still be served.
    asio::post(io, [&] {
        poller->remove(first.ours);
        ASSERT_TRUE(poller->add(second.ours, *watcher, EPOLLIN));
        second.send_byte();
    });
    io.run();
    EXPECT_EQ(watcher->events.size(), 1U);
}

TEST_F(SocketPollerTest, ADescriptorRemovedDuringABatchGetsNoEventFromIt) {
    SocketPair a;
    SocketPair b;
    auto first = std::make_shared<RecordingWatcher>();
    auto second = std::make_shared<RecordingWatcher>();
    // Whichever is told first removes both: the other's event, already taken from epoll in the
    // same batch, must not be delivered.
    auto remove_both = [&](std::uint32_t) {
        poller->remove(a.ours);
        poller->remove(b.ours);
    };
    first->action = remove_both;
    second->action = remove_both;
    ASSERT_TRUE(poller->add(a.ours, *first, EPOLLIN));
    ASSERT_TRUE(poller->add(b.ours, *second, EPOLLIN));
    a.send_byte();
    b.send_byte();
    io.run();
    EXPECT_EQ(first->events.size() + second->events.size(), 1U);
}

// A connection that ends during a batch, and whose descriptor number a new connection takes at
// once: the old connection's event, already taken from epoll, must not reach the new watcher (an
// EPOLLHUP meant for the old one would close the new one).
TEST_F(SocketPollerTest, AnEventForARemovedDescriptorIsNotDeliveredToItsNextWatcher) {
    SocketPair a;
    SocketPair b;
    SocketPair fresh;  // the new connection: idle, so its watcher has nothing to be told
    auto first = std::make_shared<RecordingWatcher>();
    auto second = std::make_shared<RecordingWatcher>();
    auto newcomer = std::make_shared<RecordingWatcher>();
    int replaced = -1;
    // Whichever is told first ends the other's connection and puts the new one on its number.
    auto replace_other = [&](int other_fd) {
        return [&, other_fd](std::uint32_t) {
            if (replaced >= 0) return;
            replaced = other_fd;
            poller->remove(other_fd);
            ASSERT_EQ(::dup2(fresh.ours, other_fd), other_fd);
            ASSERT_TRUE(poller->add(other_fd, *newcomer, EPOLLIN));
            asio::post(io, [&] {
                poller->remove(a.ours);
                poller->remove(b.ours);
            });
        };
    };
    first->action = replace_other(b.ours);
    second->action = replace_other(a.ours);
    ASSERT_TRUE(poller->add(a.ours, *first, EPOLLIN));
    ASSERT_TRUE(poller->add(b.ours, *second, EPOLLIN));
    // Both hung up before the poller looks: one batch holds an EPOLLHUP for each.
    ::close(a.theirs);
    a.theirs = -1;
    ::close(b.theirs);
    b.theirs = -1;
    io.run_for(std::chrono::seconds(10));
    ASSERT_GE(replaced, 0);
    EXPECT_TRUE((replaced == b.ours ? second : first)->events.empty());
    EXPECT_TRUE(newcomer->events.empty());
}

TEST_F(SocketPollerTest, ReportsRoomToWriteOnlyWhenAskedFor) {
    watcher->action = [&](std::uint32_t events) {
        if (events & EPOLLIN) {
            read_byte(pair.ours);
            poller->modify(pair.ours, EPOLLOUT);  // now only output
        } else {
            poller->remove(pair.ours);
        }
    };
    ASSERT_TRUE(poller->add(pair.ours, *watcher, EPOLLIN));
    pair.send_byte();
    io.run();
    ASSERT_EQ(watcher->events.size(), 2U);
    EXPECT_EQ(watcher->events[0] & EPOLLOUT, 0U) << "output was not asked for at first";
    EXPECT_EQ(watcher->events[1], static_cast<std::uint32_t>(EPOLLOUT));
}

// Even with one socket the poller asks epoll what happened, so a hang-up is reported as one
// (a wake-up taken as plain input would hide a FIN that came with the last data).
TEST_F(SocketPollerTest, WithOneSocketAHangUpArrivesAsEpollReportsIt) {
    ssize_t read_result = -2;
    watcher->action = [&](std::uint32_t) {
        char byte = 0;
        read_result = ::read(pair.ours, &byte, 1);
        poller->remove(pair.ours);
    };
    ASSERT_TRUE(poller->add(pair.ours, *watcher, EPOLLIN));
    // Once the poller waits: its first look, when added, asks epoll.
    asio::post(io, [&] {
        ::close(pair.theirs);
        pair.theirs = -1;
    });
    io.run();
    ASSERT_EQ(watcher->events.size(), 1U);
    EXPECT_EQ(watcher->events[0], static_cast<std::uint32_t>(EPOLLIN | EPOLLHUP));
    EXPECT_EQ(read_result, 0) << "end of stream";
}

TEST_F(SocketPollerTest, WithTwoSocketsAHangUpArrivesAsEpollReportsIt) {
    SocketPair other;
    watcher->action = [&](std::uint32_t) {
        poller->remove(pair.ours);
        poller->remove(other.ours);
    };
    ASSERT_TRUE(poller->add(pair.ours, *watcher, EPOLLIN));
    ASSERT_TRUE(poller->add(other.ours, *watcher, EPOLLIN));
    ::close(pair.theirs);
    pair.theirs = -1;
    io.run();
    ASSERT_EQ(watcher->events.size(), 1U);
    EXPECT_EQ(watcher->events[0] & EPOLLHUP, static_cast<std::uint32_t>(EPOLLHUP));
}

// A batch of several ready sockets is followed by another look without waiting; once nothing is
// ready the poller must go back to waiting, and input that comes later must still be delivered.
TEST_F(SocketPollerTest, AfterABusyBatchInputThatComesLaterIsDelivered) {
    SocketPair other;
    int reads = 0;
    bool armed = false;
    asio::steady_timer later(io);
    watcher->action = [&](std::uint32_t) {
        // Which socket is ready is not told to this watcher: try both.
        char byte = 0;
        reads += ::recv(pair.ours, &byte, 1, MSG_DONTWAIT) == 1;
        reads += ::recv(other.ours, &byte, 1, MSG_DONTWAIT) == 1;
        if (reads == 2 && !armed) {
            armed = true;
            later.expires_after(std::chrono::milliseconds(20));
            later.async_wait([&](const asio::error_code& ec) {
                if (!ec) other.send_byte();
            });
        }
        if (reads == 3) {
            poller->remove(pair.ours);
            poller->remove(other.ours);
        }
    };
    ASSERT_TRUE(poller->add(pair.ours, *watcher, EPOLLIN));
    ASSERT_TRUE(poller->add(other.ours, *watcher, EPOLLIN));
    pair.send_byte();
    other.send_byte();
    io.run();
    EXPECT_EQ(reads, 3);
    EXPECT_EQ(poller->watched(), 0U);
}

// A watcher that reads everything says so, and the poller then waits without looking again: each
// new message must still wake it (the set stays armed in the reactor from one wait to the next).
// Messages go over `talker`, the next one sent only once the last was read, as a client waiting
// for answers; all of `watched` is watched. Returns how many were read.
int closed_loop(asio::io_context& io, SocketPoller& poller, RecordingWatcher& watcher,
                SocketPair& talker, const std::vector<int>& watched, int messages) {
    int received = 0;
    watcher.leaves_input = false;
    watcher.action = [&](std::uint32_t) {
        char byte = 0;
        while (::recv(talker.ours, &byte, 1, MSG_DONTWAIT) == 1) {
            ++received;
        }
        if (received == messages) {
            for (const int fd : watched)
                poller.remove(fd);
            return;
        }
        asio::post(io, [&] { talker.send_byte(); });
    };
    talker.send_byte();
    io.run_for(std::chrono::seconds(10));  // a lost wake-up would wait for ever
    return received;
}

TEST_F(SocketPollerTest, AWatcherThatReadsAllIsWokenByEachNewMessage) {
    ASSERT_TRUE(poller->add(pair.ours, *watcher, EPOLLIN));
    EXPECT_EQ(closed_loop(io, *poller, *watcher, pair, {pair.ours}, 200), 200);
}

// The same with two sockets, which the poller asks epoll about.
TEST_F(SocketPollerTest, WithTwoSocketsEachNewMessageWakesTheReader) {
    SocketPair other;
    ASSERT_TRUE(poller->add(pair.ours, *watcher, EPOLLIN));
    ASSERT_TRUE(poller->add(other.ours, *watcher, EPOLLIN));
    EXPECT_EQ(closed_loop(io, *poller, *watcher, other, {pair.ours, other.ours}, 100), 100);
}

// A session that stops taking input (its queue of answers is full) and takes it again later:
// what came meanwhile must be reported when input is watched again, although no new byte comes.
TEST_F(SocketPollerTest, InputThatCameWhileNotWatchedIsReportedWhenWatchedAgain) {
    watcher->leaves_input = false;
    asio::steady_timer later(io);
    watcher->action = [&](std::uint32_t) {
        if (watcher->events.size() == 1) {
            EXPECT_EQ(read_byte(pair.ours), 'a');
            poller->modify(pair.ours, 0);  // not watched for input any more
            pair.send_byte('b');
            later.expires_after(std::chrono::milliseconds(20));
            later.async_wait([&](const asio::error_code& ec) {
                if (!ec) poller->modify(pair.ours, EPOLLIN);
            });
            return;
        }
        EXPECT_EQ(read_byte(pair.ours), 'b');
        poller->remove(pair.ours);
    };
    ASSERT_TRUE(poller->add(pair.ours, *watcher, EPOLLIN));
    pair.send_byte('a');
    io.run_for(std::chrono::seconds(10));  // a lost wake-up would wait for ever
    EXPECT_EQ(watcher->events.size(), 2U);
}

// A watcher that reads only part of what came says it may have left input: it is told again
// though nothing new arrives.
TEST_F(SocketPollerTest, AWatcherThatLeavesInputIsToldAgain) {
    int received = 0;
    watcher->action = [&](std::uint32_t) {
        received += read_byte(pair.ours) == 'x';
        if (received == 3) poller->remove(pair.ours);
    };
    ASSERT_TRUE(poller->add(pair.ours, *watcher, EPOLLIN));
    const char three[3] = {'x', 'x', 'x'};
    ASSERT_EQ(::write(pair.theirs, three, 3), 3);
    io.run_for(std::chrono::seconds(10));  // a lost wake-up would wait for ever
    EXPECT_EQ(received, 3);
}

TEST_F(SocketPollerTest, RefusesADescriptorWatchedTwiceOrInvalid) {
    ASSERT_TRUE(poller->add(pair.ours, *watcher, EPOLLIN));
    EXPECT_FALSE(poller->add(pair.ours, *watcher, EPOLLIN));
    EXPECT_EQ(errno, EEXIST);
    EXPECT_FALSE(poller->add(-1, *watcher, EPOLLIN));
    EXPECT_EQ(errno, EBADF);
    int closed = ::dup(pair.theirs);
    ::close(closed);
    EXPECT_FALSE(poller->add(closed, *watcher, EPOLLIN));
    EXPECT_EQ(errno, EBADF);
    EXPECT_EQ(poller->watched(), 1U);
    poller->remove(pair.ours);
}

}  // namespace
