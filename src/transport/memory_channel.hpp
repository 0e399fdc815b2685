#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <limits>
#include <span>
#include <string>

#include "transport/channel.hpp"

// A connected pair of in-memory channels, a socket pair without the kernel, for driving sessions
// in tests on a manual clock: what one end writes the other reads, in order, and each call
// reports what a non-blocking socket would. Failures are injected on purpose: short writes, a
// peer that stops reading (the bytes in flight fill a window and writes take nothing more), and
// a reset.
namespace mblab::transport {

class MemoryPair {
  private:
    // One direction: the bytes written and not yet read.
    struct Direction {
        std::deque<std::uint8_t> bytes;
        std::size_t window = std::numeric_limits<std::size_t>::max();
        std::size_t max_write = std::numeric_limits<std::size_t>::max();
        std::size_t written = 0;  // in all
        bool shut = false;
    };

  public:
    class End final : public Channel {
      public:
        End(const End&) = delete;
        End& operator=(const End&) = delete;

        Io read(std::span<std::uint8_t> out) override;
        // Taken in order, as far as room goes.
        Io writev(std::span<const iovec> buffers) override;
        // The pair knows: bytes, or an end of input, still to read.
        bool input_may_remain() const override { return readable(); }
        // The other end reads the end of input once it has read what came before.
        void shutdown_write() override { out_.shut = true; }
        // As a socket's close: the other end reads the end of input, or a reset when input was
        // left unread here (RFC 1122 4.2.2.13); this end moves no more.
        void close() override;
        PeerIdentity peer() const override { return {}; }
        const std::string& error() const override { return error_; }
        // Both ends fail from now on (ECONNRESET), and what was in flight is lost.
        void reset();

        // What a readiness loop would be told.
        bool readable() const { return reset_ || !in_.bytes.empty() || in_.shut; }
        bool writable() const;
        std::size_t pending() const { return in_.bytes.size(); }
        bool at_end_of_input() const { return in_.bytes.empty() && in_.shut; }
        bool is_reset() const { return reset_; }
        bool is_closed() const { return closed_; }
        // Bytes this end has written in all (taken by the pair, read or not).
        std::size_t written() const { return out_.written; }

        // Bytes this end may have in flight, unread by the other end; 0 and a peer that never
        // reads: every write would block.
        void set_window(std::size_t bytes) { out_.window = bytes; }
        // Each write takes at most this many bytes (short writes).
        void set_max_write(std::size_t bytes) { out_.max_write = bytes; }

      private:
        friend class MemoryPair;
        End(Direction& in, Direction& out, bool& reset) : in_(in), out_(out), reset_(reset) {}
        std::size_t room() const;

        Direction& in_;
        Direction& out_;
        bool& reset_;
        bool closed_ = false;
        std::string error_;
    };

    MemoryPair() = default;
    MemoryPair(const MemoryPair&) = delete;
    MemoryPair& operator=(const MemoryPair&) = delete;

    End& client() { return client_; }
    End& server() { return server_; }
    const End& client() const { return client_; }
    const End& server() const { return server_; }

  private:
    Direction to_server_;
    Direction to_client_;
    bool reset_ = false;
    End client_{to_client_, to_server_, reset_};
    End server_{to_server_, to_client_, reset_};
};

}  // namespace mblab::transport
