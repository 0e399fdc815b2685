#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

namespace mblab::protocol {

// Registers as they sit on the wire (big-endian pairs), read without copying.
class RegisterView {
  public:
    RegisterView() = default;
    explicit RegisterView(std::span<const std::uint8_t> bytes) : bytes_(bytes) {}

    std::size_t size() const { return bytes_.size() / 2; }
    bool empty() const { return size() == 0; }
    std::uint16_t operator[](std::size_t i) const {
        return static_cast<std::uint16_t>((bytes_[2 * i] << 8) | bytes_[2 * i + 1]);
    }
    std::span<const std::uint8_t> bytes() const { return bytes_; }

  private:
    std::span<const std::uint8_t> bytes_;
};

// Packed bits as on the wire: bit i is bit (i % 8) of byte i / 8, LSB first.
class BitView {
  public:
    BitView() = default;
    BitView(std::span<const std::uint8_t> bytes, std::size_t count)
        : bytes_(bytes), count_(count) {}

    std::size_t size() const { return count_; }
    bool operator[](std::size_t i) const { return (bytes_[i / 8] >> (i % 8)) & 1U; }
    std::span<const std::uint8_t> bytes() const { return bytes_; }

  private:
    std::span<const std::uint8_t> bytes_;
    std::size_t count_ = 0;
};

}  // namespace mblab::protocol
