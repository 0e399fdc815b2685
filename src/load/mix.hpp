#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "conformance/pattern.hpp"
#include "protocol/result.hpp"

// The traffic generator's request mix, as `--mix` writes it (docs/load.md):
//   fc3:125=70,fc16:10=20,fc1:100@512=10
// Each entry is fcCODE[:QUANTITY][@ADDRESS][=WEIGHT]. CODE is decimal (fc16 is 0x10) or hex
// with 0x; QUANTITY is registers or bits (default 1); ADDRESS defaults to 0 for reads and to
// 0x0010 for writes (CTP 7.8.1.1 keeps writes off the first registers, where a SEMI
// signature may sit); WEIGHT is the entry's share of requests (default 1).
namespace mblab::load {

struct MixEntry {
    std::uint8_t function = 3;
    std::uint16_t quantity = 1;
    std::uint16_t address = 0;
    std::uint32_t weight = 1;
    std::string text;  // the entry as written, for reports: "fc3:125"
};

protocol::Result<std::vector<MixEntry>, std::string> parse_mix(std::string_view text);

// The request of an entry and the answer a correct device gives, with transaction id 00 00
// and {unit} for the unit id (the load runner owns both).
struct MixExchange {
    conformance::Pattern request;
    conformance::Pattern expect;
};

MixExchange mix_exchange(const MixEntry& entry);

// The function codes --mix accepts, for the error message and the docs.
inline constexpr std::string_view kMixFunctions = "1, 2, 3, 4, 5, 6, 15, 16";

}  // namespace mblab::load
