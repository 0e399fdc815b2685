#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "protocol/result.hpp"

// Addresses as users bring them from device manuals. On the wire an address is a 0-based PDU
// offset; manuals often give 1-based numbers or Modicon references (40001, 400001, 4x00001), and
// that difference of one is the most common reason a first read gets exception 02.
namespace mblab::cli {

// The four data tables, numbered by their Modicon reference digit.
enum class DataTable : std::uint8_t { Coils = 0, Discretes = 1, Input = 3, Holding = 4 };

// "holding registers": for messages.
const char* table_name(DataTable table);

// ADDR as typed for a command that addresses `table`:
//   a number (decimal or 0x hex), 0-based, or 1-based when `base` is 1 (so 0 is refused);
//   a reference, 1-based whatever `base` says: the table digit, x and 4 or 5 digits (4x0001,
//   4x00001), or the 6-digit form (400001, 000001 for coil 1). 0x0001 stays hex: 0x means hex
//   everywhere on mblab's command line, so coil references take the 6-digit form.
// A reference to another table is refused naming both.
protocol::Result<std::uint16_t, std::string> parse_address(const std::string& text,
                                                           const char* name, DataTable table,
                                                           int base);

// For an exception 02 at ADDR `text`, given as a plain 0-based number: when it reads as a
// 5-digit Modicon reference to `table` (40001 for holding registers), what to type instead.
std::optional<std::string> reference_hint(const std::string& text, DataTable table, int base);

}  // namespace mblab::cli
