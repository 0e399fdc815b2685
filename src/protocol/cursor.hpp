#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>

namespace mblab::protocol {

// Bounds-checked big-endian reader over a non-owning byte view. A read that would pass the end
// returns false and leaves the cursor where it was.
class ReadCursor {
  public:
    explicit ReadCursor(std::span<const std::uint8_t> bytes) : bytes_(bytes) {}

    std::size_t remaining() const { return bytes_.size() - pos_; }
    std::size_t position() const { return pos_; }
    bool empty() const { return remaining() == 0; }

    bool read_u8(std::uint8_t& out) {
        if (remaining() < 1) return false;
        out = bytes_[pos_++];
        return true;
    }
    bool read_u16(std::uint16_t& out) {
        if (remaining() < 2) return false;
        out = static_cast<std::uint16_t>((bytes_[pos_] << 8) | bytes_[pos_ + 1]);
        pos_ += 2;
        return true;
    }
    bool read_bytes(std::size_t count, std::span<const std::uint8_t>& out) {
        if (remaining() < count) return false;
        out = bytes_.subspan(pos_, count);
        pos_ += count;
        return true;
    }
    std::span<const std::uint8_t> rest() const { return bytes_.subspan(pos_); }

  private:
    std::span<const std::uint8_t> bytes_;
    std::size_t pos_ = 0;
};

// Big-endian writer into a caller-provided buffer. Running out of space sets a sticky overflow
// flag instead of writing past the end; check ok() once at the end.
class WriteCursor {
  public:
    explicit WriteCursor(std::span<std::uint8_t> out) : out_(out) {}

    bool ok() const { return !overflow_; }
    std::size_t size() const { return pos_; }
    std::span<const std::uint8_t> written() const { return out_.first(pos_); }

    void put_u8(std::uint8_t value) {
        if (!reserve(1)) return;
        out_[pos_++] = value;
    }
    void put_u16(std::uint16_t value) {
        if (!reserve(2)) return;
        out_[pos_++] = static_cast<std::uint8_t>(value >> 8);
        out_[pos_++] = static_cast<std::uint8_t>(value & 0xFF);
    }
    void put_bytes(std::span<const std::uint8_t> bytes) {
        if (!reserve(bytes.size())) return;
        if (!bytes.empty()) std::memcpy(out_.data() + pos_, bytes.data(), bytes.size());
        pos_ += bytes.size();
    }
    // Overwrites a byte already written, e.g. a byte count known only at the end.
    void patch_u8(std::size_t at, std::uint8_t value) {
        if (at < pos_) out_[at] = value;
    }

  private:
    bool reserve(std::size_t count) {
        if (overflow_ || out_.size() - pos_ < count) {
            overflow_ = true;
            return false;
        }
        return true;
    }

    std::span<std::uint8_t> out_;
    std::size_t pos_ = 0;
    bool overflow_ = false;
};

}  // namespace mblab::protocol
