#pragma once

#include <openssl/bio.h>

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

// The byte queues between a TlsChannel and the network. OpenSSL's memory BIO would do, but every
// record asks its BIOs a dozen questions (pending? flush? eof?) through BIO_ctrl(), and the
// memory BIO answers each with a walk through its buffer bookkeeping: about 2,000 instructions per
// request and answer of a Modbus/TCP Security session, a tenth of the server's TLS work. Here the
// BIO answers from two integers, and the channel's owner reads what OpenSSL wrote, and writes what
// the network sent, in place.
namespace mblab::security {

class ByteQueue {
  public:
    std::span<const std::uint8_t> bytes() const { return std::span(bytes_).subspan(head_); }
    std::size_t size() const { return bytes_.size() - head_; }
    bool empty() const { return head_ == bytes_.size(); }

    void append(std::span<const std::uint8_t> more);
    // Takes up to out.size() bytes from the front; returns how many.
    std::size_t take(std::span<std::uint8_t> out);
    // Drops `count` bytes from the front (at most all of them).
    void drop(std::size_t count);
    // Gives the storage back when nothing is queued (the capacity a handshake's flights left).
    void release();

  private:
    // Bytes before head_ are taken; the vector keeps its capacity, so a session that sends and
    // receives records of a steady size allocates nothing after its first ones.
    std::vector<std::uint8_t> bytes_;
    std::size_t head_ = 0;
};

// A BIO over `queue`, which must outlive it: BIO_write() appends, BIO_read() takes from the
// front and, when the queue is empty, says "retry" (more may come), never end of file.
// Null when OpenSSL cannot make one.
BIO* new_queue_bio(ByteQueue& queue);

}  // namespace mblab::security
