#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

// The communication event log of [APP] 6.9 (FC 0C): the last 64 event bytes, newest first.
namespace mblab::device {

namespace event {
inline constexpr std::uint8_t kReceive = 0x80;
inline constexpr std::uint8_t kReceiveOverrun = 0x10;
inline constexpr std::uint8_t kReceiveListenOnly = 0x20;
inline constexpr std::uint8_t kReceiveBroadcast = 0x40;
inline constexpr std::uint8_t kSend = 0x40;
inline constexpr std::uint8_t kSendReadException = 0x01;   // exception 01..03
inline constexpr std::uint8_t kSendAbortException = 0x02;  // exception 04
inline constexpr std::uint8_t kSendBusyException = 0x04;   // exception 05, 06
inline constexpr std::uint8_t kSendNakException = 0x08;    // exception 07
inline constexpr std::uint8_t kSendListenOnly = 0x20;
inline constexpr std::uint8_t kEnteredListenOnly = 0x04;
inline constexpr std::uint8_t kRestart = 0x00;
}  // namespace event

class EventLog {
  public:
    static constexpr std::size_t kCapacity = 64;

    void add(std::uint8_t event) {
        head_ = (head_ + kCapacity - 1) % kCapacity;
        ring_[head_] = event;
        if (size_ < kCapacity) ++size_;
    }
    void clear() { size_ = 0; }
    std::size_t size() const { return size_; }
    std::uint8_t newest(std::size_t i) const { return ring_[(head_ + i) % kCapacity]; }
    // Copies newest first; returns the bytes written.
    std::size_t copy(std::span<std::uint8_t> out) const {
        std::size_t n = size_ < out.size() ? size_ : out.size();
        for (std::size_t i = 0; i < n; ++i)
            out[i] = newest(i);
        return n;
    }

  private:
    std::array<std::uint8_t, kCapacity> ring_{};
    std::size_t head_ = 0;
    std::size_t size_ = 0;
};

}  // namespace mblab::device
