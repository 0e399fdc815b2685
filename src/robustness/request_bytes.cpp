#include "robustness/request_bytes.hpp"

#include <algorithm>

namespace mblab::robustness {

void put16(std::vector<std::uint8_t>& out, std::uint16_t value) {
    out.push_back(static_cast<std::uint8_t>(value >> 8));
    out.push_back(static_cast<std::uint8_t>(value));
}

std::vector<std::uint8_t> words(std::uint8_t function,
                                std::initializer_list<std::uint16_t> fields) {
    std::vector<std::uint8_t> out{function};
    for (auto field : fields)
        put16(out, field);
    return out;
}

std::vector<std::uint8_t> multiple_write(std::uint8_t function, std::uint16_t address,
                                         std::uint16_t quantity, std::uint8_t byte_count,
                                         std::size_t data) {
    auto out = words(function, {address, quantity});
    out.push_back(byte_count);
    out.resize(out.size() + data, 0);
    return out;
}

std::vector<std::uint8_t> read_write(std::uint16_t read_address, std::uint16_t read_quantity,
                                     std::uint16_t write_address, std::uint16_t write_quantity,
                                     std::uint8_t byte_count, std::size_t data) {
    auto out = words(0x17, {read_address, read_quantity, write_address, write_quantity});
    out.push_back(byte_count);
    out.resize(out.size() + data, 0);
    return out;
}

std::uint8_t byte_count_for(std::uint8_t function, std::uint32_t quantity) {
    const std::uint32_t bytes = function == 0x0F ? (quantity + 7) / 8 : 2 * quantity;
    return static_cast<std::uint8_t>(std::min<std::uint32_t>(bytes, 0xFF));
}

}  // namespace mblab::robustness
