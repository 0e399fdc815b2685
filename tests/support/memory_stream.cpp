#include "support/memory_stream.hpp"

#include <algorithm>

namespace mblab::test {

StreamIo StreamPair::End::read(std::span<std::uint8_t> out) {
    if (reset_) return {StreamIo::Status::Reset, 0};
    if (in_.bytes.empty()) {
        return {in_.shut ? StreamIo::Status::EndOfInput : StreamIo::Status::WouldBlock, 0};
    }
    const auto count = std::min(out.size(), in_.bytes.size());
    std::copy_n(in_.bytes.begin(), count, out.begin());
    in_.bytes.erase(in_.bytes.begin(), in_.bytes.begin() + static_cast<std::ptrdiff_t>(count));
    return {StreamIo::Status::Done, count};
}

std::size_t StreamPair::End::room() const {
    const auto in_flight = out_.bytes.size();
    const auto window_room = out_.window > in_flight ? out_.window - in_flight : 0;
    return std::min(window_room, out_.max_write);
}

bool StreamPair::End::writable() const {
    return !reset_ && !out_.shut && room() > 0;
}

StreamIo StreamPair::End::write(std::span<const std::uint8_t> bytes) {
    const std::span<const std::uint8_t> one[] = {bytes};
    return write(one);
}

StreamIo StreamPair::End::write(std::span<const std::span<const std::uint8_t>> buffers) {
    if (reset_) return {StreamIo::Status::Reset, 0};
    const auto space = room();
    std::size_t taken = 0;
    for (const auto& buffer : buffers) {
        const auto count = std::min(space - taken, buffer.size());
        out_.bytes.insert(out_.bytes.end(), buffer.begin(),
                          buffer.begin() + static_cast<std::ptrdiff_t>(count));
        taken += count;
        if (taken == space) break;
    }
    out_.written += taken;
    if (taken == 0) {
        const bool asked = std::any_of(buffers.begin(), buffers.end(),
                                       [](const auto& buffer) { return !buffer.empty(); });
        if (asked) return {StreamIo::Status::WouldBlock, 0};
    }
    return {StreamIo::Status::Done, taken};
}

void StreamPair::End::reset() {
    reset_ = true;
    in_.bytes.clear();
    out_.bytes.clear();
}

}  // namespace mblab::test
