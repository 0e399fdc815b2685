#include "transport/memory_channel.hpp"

#include <algorithm>
#include <cerrno>

namespace mblab::transport {

Io MemoryPair::End::read(std::span<std::uint8_t> out) {
    if (reset_) return Io::failed(ECONNRESET);
    if (closed_) return Io::failed(EBADF);
    if (in_.bytes.empty()) return in_.shut ? Io::end_of_input() : Io::would_block();
    const auto count = std::min(out.size(), in_.bytes.size());
    std::copy_n(in_.bytes.begin(), count, out.begin());
    in_.bytes.erase(in_.bytes.begin(), in_.bytes.begin() + static_cast<std::ptrdiff_t>(count));
    return Io::done(count);
}

std::size_t MemoryPair::End::room() const {
    const auto in_flight = out_.bytes.size();
    const auto window_room = out_.window > in_flight ? out_.window - in_flight : 0;
    return std::min(window_room, out_.max_write);
}

bool MemoryPair::End::writable() const {
    return !reset_ && !out_.shut && room() > 0;
}

Io MemoryPair::End::writev(std::span<const iovec> buffers) {
    if (reset_) return Io::failed(ECONNRESET);
    if (closed_ || out_.shut) return Io::failed(EPIPE);
    const auto space = room();
    std::size_t taken = 0;
    bool asked = false;
    for (const auto& buffer : buffers) {
        asked = asked || buffer.iov_len > 0;
        const auto count = std::min(space - taken, buffer.iov_len);
        const auto* bytes = static_cast<const std::uint8_t*>(buffer.iov_base);
        out_.bytes.insert(out_.bytes.end(), bytes, bytes + count);
        taken += count;
        if (taken == space) break;
    }
    out_.written += taken;
    if (taken == 0 && asked) return Io::would_block();
    return Io::done(taken);
}

void MemoryPair::End::close() {
    if (closed_) return;
    closed_ = true;
    out_.shut = true;
    // As a socket closed with input unread: a reset, which loses what the peer has not read.
    if (!in_.bytes.empty()) reset();
}

void MemoryPair::End::reset() {
    reset_ = true;
    in_.bytes.clear();
    out_.bytes.clear();
}

}  // namespace mblab::transport
