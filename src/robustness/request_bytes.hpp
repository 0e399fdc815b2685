#pragma once

#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <vector>

// Requests spelled out byte by byte, their fields as the caller gives them, right or wrong: the
// fixed cases and the pairwise rows build their PDUs with these.
namespace mblab::robustness {

void put16(std::vector<std::uint8_t>& out, std::uint16_t value);

// A function code followed by 16-bit fields.
std::vector<std::uint8_t> words(std::uint8_t function, std::initializer_list<std::uint16_t> fields);

// FC 0F / 10 with a byte count and `data` bytes of payload (zeros), whatever the quantity says.
std::vector<std::uint8_t> multiple_write(std::uint8_t function, std::uint16_t address,
                                         std::uint16_t quantity, std::uint8_t byte_count,
                                         std::size_t data);

// FC 17 with a byte count and `data` bytes of payload (zeros), whatever the write quantity says.
std::vector<std::uint8_t> read_write(std::uint16_t read_address, std::uint16_t read_quantity,
                                     std::uint16_t write_address, std::uint16_t write_quantity,
                                     std::uint8_t byte_count, std::size_t data);

// The byte count FC 0F (bits) or FC 10 / 17 (registers) should carry for `quantity`, as far as
// a byte holds it.
std::uint8_t byte_count_for(std::uint8_t function, std::uint32_t quantity);

}  // namespace mblab::robustness
