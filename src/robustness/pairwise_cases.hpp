#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "robustness/recon.hpp"
#include "robustness/writable_range.hpp"

// The pairwise class: a public function's request fields and the MBAP header's are the
// parameters, each with its boundary values (0, 1, the limit and one past it, 0x7FFF, 0xFFFE,
// 0xFFFF, what reconnaissance found; byte counts and lengths right, one off, 0, 0xFF), and each
// row of a covering array (robustness/pairwise.hpp) is one request. Every pair of two fields'
// values is tried without trying every combination.
namespace mblab::robustness {

struct PairwiseFrame {
    std::string name;  // "FC 0x03 unit 0 address 0xFFFF quantity 126 length right"
    std::uint8_t unit = 0;
    std::vector<std::uint8_t> pdu;
    std::optional<std::uint16_t> transaction;  // nullopt: the generator's next one
    std::uint16_t protocol = 0;
    std::optional<std::uint16_t> length;  // nullopt: the right one
};

// The rows of every function whose request is laid out here (FC 01 to 06, 08, 0F, 10, 16, 17,
// 2B), served or not (a device may parse a request before it finds it does not serve it), a
// function at a time in turn: the first row of each (the nominal request), then the second of each,
// ... Writes aim at `writable` (and at its edges) when there is one. With `mbap` false (a serial
// line) the MBAP-only fields are left out and the unit id, which is the line's address, stays.
std::vector<PairwiseFrame> pairwise_frames(const Recon& recon,
                                           const std::optional<WritableRange>& writable, bool mbap);

}  // namespace mblab::robustness
