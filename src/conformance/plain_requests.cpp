#include "conformance/plain_requests.hpp"

#include <algorithm>
#include <span>

namespace mblab::conformance {

namespace {

struct PlainRequest {
    std::uint8_t function;
    std::vector<std::uint8_t> pdu;
};

// A write puts zero (coil 0 off, register 0 zero) or leaves the value as it was (FC 16's AND mask
// FFFF, which harmless_request_pdu takes as it is).
const std::vector<PlainRequest>& plain_requests() {
    static const std::vector<PlainRequest> table = {
        {0x01, {0x01, 0x00, 0x00, 0x00, 0x01}},
        {0x02, {0x02, 0x00, 0x00, 0x00, 0x01}},
        {0x03, {0x03, 0x00, 0x00, 0x00, 0x01}},
        {0x04, {0x04, 0x00, 0x00, 0x00, 0x01}},
        {0x05, {0x05, 0x00, 0x00, 0x00, 0x00}},
        {0x06, {0x06, 0x00, 0x00, 0x00, 0x00}},
        {0x07, {0x07}},
        {0x08, {0x08, 0x00, 0x00, 0x12, 0x34}},
        {0x0B, {0x0B}},
        {0x0C, {0x0C}},
        {0x0F, {0x0F, 0x00, 0x00, 0x00, 0x01, 0x01, 0x00}},
        {0x10, {0x10, 0x00, 0x00, 0x00, 0x01, 0x02, 0x00, 0x00}},
        {0x11, {0x11}},
        // File 1, record 0, one register; reference type 6.
        {0x14, {0x14, 0x07, 0x06, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01}},
        {0x15, {0x15, 0x09, 0x06, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00}},
        {0x16, {0x16, 0x00, 0x00, 0xFF, 0xFF, 0x00, 0x00}},
        {0x17, {0x17, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x02, 0x00, 0x00}},
        {0x18, {0x18, 0x00, 0x00}},
        // Basic device identification as a stream from object 0.
        {0x2B, {0x2B, 0x0E, 0x01, 0x00}},
    };
    return table;
}

}  // namespace

std::optional<std::vector<std::uint8_t>> plain_request_pdu(std::uint8_t function) {
    const auto& table = plain_requests();
    const auto found = std::find_if(table.begin(), table.end(),
                                    [&](const PlainRequest& r) { return r.function == function; });
    if (found == table.end()) return std::nullopt;
    return found->pdu;
}

std::span<const std::uint8_t> functions_with_plain_requests() {
    static const auto codes = [] {
        std::vector<std::uint8_t> out;
        for (const auto& request : plain_requests())
            out.push_back(request.function);
        return out;
    }();
    return codes;
}

std::optional<std::vector<std::uint8_t>> harmless_request_pdu(std::uint8_t function) {
    switch (function) {
        case 0x05:
            return std::vector<std::uint8_t>{0x05, 0x00, 0x00, 0x12, 0x34};
        case 0x06:
            return std::vector<std::uint8_t>{0x06, 0x00, 0x00};
        case 0x0F:
            return std::vector<std::uint8_t>{0x0F, 0x00, 0x00, 0x00, 0x00, 0x00};
        case 0x10:
            return std::vector<std::uint8_t>{0x10, 0x00, 0x00, 0x00, 0x00, 0x00};
        case 0x15:
            return std::vector<std::uint8_t>{0x15, 0x00};
        case 0x17:
            return std::vector<std::uint8_t>{0x17, 0x00, 0x00, 0x00, 0x01,
                                             0x00, 0x00, 0x00, 0x00, 0x00};
        default:
            return plain_request_pdu(function);
    }
}

namespace {

bool writes_a_coil(std::uint8_t function) {
    return function == 0x05 || function == 0x0F;
}

bool writes_a_register(std::uint8_t function) {
    return function == 0x06 || function == 0x10 || function == 0x17;
}

}  // namespace

std::optional<std::vector<std::uint8_t>> read_before_write_back(std::uint8_t function) {
    if (writes_a_coil(function)) return plain_request_pdu(0x01);
    if (writes_a_register(function)) return plain_request_pdu(0x03);
    return std::nullopt;
}

std::optional<std::vector<std::uint8_t>> write_back_pdu(std::uint8_t function,
                                                        std::span<const std::uint8_t> read_answer) {
    if (writes_a_coil(function)) {
        if (read_answer.size() != 3 || read_answer[0] != 0x01 || read_answer[1] != 1) {
            return std::nullopt;
        }
        const bool on = (read_answer[2] & 0x01) != 0;
        if (function == 0x05) {
            return std::vector<std::uint8_t>{0x05, 0x00, 0x00,
                                             on ? std::uint8_t{0xFF} : std::uint8_t{0x00}, 0x00};
        }
        return std::vector<std::uint8_t>{
            0x0F, 0x00, 0x00, 0x00, 0x01, 0x01, on ? std::uint8_t{1} : std::uint8_t{0}};
    }
    if (!writes_a_register(function) || read_answer.size() != 4 || read_answer[0] != 0x03 ||
        read_answer[1] != 2) {
        return std::nullopt;
    }
    const std::uint8_t high = read_answer[2];
    const std::uint8_t low = read_answer[3];
    switch (function) {
        case 0x06:
            return std::vector<std::uint8_t>{0x06, 0x00, 0x00, high, low};
        case 0x10:
            return std::vector<std::uint8_t>{0x10, 0x00, 0x00, 0x00, 0x01, 0x02, high, low};
        default:  // 0x17: read register 0, write the same value back to it
            return std::vector<std::uint8_t>{0x17, 0x00, 0x00, 0x00, 0x01, 0x00,
                                             0x00, 0x00, 0x01, 0x02, high, low};
    }
}

}  // namespace mblab::conformance
