#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <limits>
#include <span>

// A connected pair of in-memory byte streams, a socket pair without the kernel, for driving
// sans-I/O sessions: what one end writes the other reads, in order, and each call reports what a
// non-blocking socket would. Failures are injected on purpose: short writes, a peer that stops
// reading (the bytes in flight fill a window and writes take nothing more), and a reset.
namespace mblab::test {

struct StreamIo {
    enum class Status : std::uint8_t {
        Done,        // `bytes` moved (at least one)
        WouldBlock,  // nothing to read yet, or no room to write
        EndOfInput,  // the other end shut its sending side and everything was read
        Reset,       // the connection was reset
    };
    Status status = Status::Done;
    std::size_t bytes = 0;
};

class StreamPair {
  public:
    class End;

  private:
    // One direction: the bytes written and not yet read.
    struct Channel {
        std::deque<std::uint8_t> bytes;
        std::size_t window = std::numeric_limits<std::size_t>::max();
        std::size_t max_write = std::numeric_limits<std::size_t>::max();
        std::size_t written = 0;  // in all
        bool shut = false;
    };

  public:
    class End {
      public:
        End(const End&) = delete;
        End& operator=(const End&) = delete;

        StreamIo read(std::span<std::uint8_t> out);
        StreamIo write(std::span<const std::uint8_t> bytes);
        // Several buffers as one gathered write (sendmsg): taken in order, as far as room goes.
        StreamIo write(std::span<const std::span<const std::uint8_t>> buffers);
        // The other end reads the end of input once it has read what came before.
        void shutdown_write() { out_.shut = true; }
        // Both ends fail from now on, and what was in flight is lost.
        void reset();

        std::size_t readable() const { return in_.bytes.size(); }
        bool at_end_of_input() const { return in_.bytes.empty() && in_.shut; }
        bool writable() const;
        bool is_reset() const { return reset_; }
        // Bytes this end has written in all (taken by the stream, read or not).
        std::size_t written() const { return out_.written; }

        // Bytes this end may have in flight, unread by the other end; 0 and a peer that never
        // reads: every write would block.
        void set_window(std::size_t bytes) { out_.window = bytes; }
        // Each write takes at most this many bytes (short writes).
        void set_max_write(std::size_t bytes) { out_.max_write = bytes; }

      private:
        friend class StreamPair;
        End(Channel& in, Channel& out, bool& reset) : in_(in), out_(out), reset_(reset) {}
        std::size_t room() const;

        Channel& in_;
        Channel& out_;
        bool& reset_;
    };

    StreamPair() = default;
    StreamPair(const StreamPair&) = delete;
    StreamPair& operator=(const StreamPair&) = delete;

    End& client() { return client_; }
    End& server() { return server_; }
    const End& client() const { return client_; }
    const End& server() const { return server_; }

  private:
    Channel to_server_;
    Channel to_client_;
    bool reset_ = false;
    End client_{to_client_, to_server_, reset_};
    End server_{to_server_, to_client_, reset_};
};

}  // namespace mblab::test
