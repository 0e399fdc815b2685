#include "robustness/recon.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <array>

#include "conformance/plain_requests.hpp"

namespace mblab::robustness {

namespace {

std::vector<std::uint8_t> read_holding(std::uint16_t address, std::uint16_t quantity) {
    return {0x03, static_cast<std::uint8_t>(address >> 8), static_cast<std::uint8_t>(address),
            static_cast<std::uint8_t>(quantity >> 8), static_cast<std::uint8_t>(quantity)};
}

bool read_answered(const std::optional<std::vector<std::uint8_t>>& answer, std::uint16_t quantity) {
    return answer && answer->size() == 2U + 2U * quantity && (*answer)[0] == 0x03 &&
           (*answer)[1] == 2 * quantity;
}

}  // namespace

bool Recon::serves(std::uint8_t function) const {
    return std::find(served.begin(), served.end(), function) != served.end();
}

std::optional<std::vector<std::uint8_t>> probe_request(std::uint8_t function, bool allow_writes) {
    return allow_writes ? conformance::plain_request_pdu(function)
                        : conformance::harmless_request_pdu(function);
}

std::optional<std::string> reconnoitre(const Ask& ask, const ReconOptions& options, Recon& out) {
    out.unit = options.unit;
    for (std::uint8_t function : conformance::functions_with_plain_requests()) {
        const auto request = probe_request(function, options.allow_writes);
        if (!request) continue;
        const auto answer = ask(options.unit, *request);
        if (!answer || answer->empty()) {
            out.silent.push_back(function);
        } else if (answer->size() >= 2 && (*answer)[0] == (function | 0x80) &&
                   (*answer)[1] == 0x01) {
            out.not_served.push_back(function);
        } else {
            out.served.push_back(function);
        }
    }
    static constexpr std::array<std::uint16_t, 5> kCandidates{0, 1, 100, 1000, 40000};
    std::optional<std::uint16_t> readable;
    if (options.check_address) {
        if (read_answered(ask(options.unit, read_holding(*options.check_address, 1)), 1))
            readable = options.check_address;
    } else {
        for (std::uint16_t address : kCandidates) {
            if (read_answered(ask(options.unit, read_holding(address, 1)), 1)) {
                readable = address;
                break;
            }
        }
    }
    if (!readable) {
        return options.check_address
                   ? fmt::format(
                         "holding register {} does not answer FC 03 with unit {}: the "
                         "liveness check needs one that does",
                         *options.check_address, options.unit)
                   : fmt::format(
                         "no holding register at 0, 1, 100, 1000 or 40000 answers FC 03 "
                         "with unit {}: the liveness check needs one (try --unit)",
                         options.unit);
    }
    out.check_address = *readable;
    if (options.max_read) {
        out.max_read = *options.max_read;
        out.source = "declared";
    } else {
        // The largest quantity answered: 1 is, 125 is the protocol's limit.
        std::uint16_t good = 1;
        std::uint16_t bad = 126;
        while (bad - good > 1) {
            const auto middle = static_cast<std::uint16_t>((good + bad) / 2);
            if (read_answered(ask(options.unit, read_holding(*readable, middle)), middle)) {
                good = middle;
            } else {
                bad = middle;
            }
        }
        out.max_read = good;
    }
    out.answers_unit_0 = read_answered(ask(0, read_holding(*readable, 1)), 1);
    out.answers_unit_255 = read_answered(ask(0xFF, read_holding(*readable, 1)), 1);
    return std::nullopt;
}

}  // namespace mblab::robustness
