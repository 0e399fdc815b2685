#include "protocol/lrc.hpp"

namespace mblab::protocol {

std::uint8_t lrc(std::span<const std::uint8_t> bytes) {
    unsigned sum = 0;
    for (std::uint8_t byte : bytes)
        sum += byte;
    return static_cast<std::uint8_t>(-sum);
}

}  // namespace mblab::protocol
