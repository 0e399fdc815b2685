#include "robustness/recon.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <array>

#include "conformance/plain_requests.hpp"
#include "protocol/request.hpp"
#include "protocol/request_template.hpp"

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

AddressRange span_of(std::uint16_t address, std::uint16_t quantity) {
    return {address, static_cast<std::uint16_t>(address + quantity - 1)};
}

}  // namespace

const char* table_name(Table table) {
    static constexpr std::array<const char*, kTableCount> kNames{
        "coils", "discrete inputs", "holding registers", "input registers"};
    return kNames[static_cast<std::size_t>(table)];
}

const char* table_key(Table table) {
    static constexpr std::array<const char*, kTableCount> kKeys{
        "coils", "discrete_inputs", "holding_registers", "input_registers"};
    return kKeys[static_cast<std::size_t>(table)];
}

void AnsweredRanges::add(Table table, AddressRange range) {
    auto& ranges = tables_[static_cast<std::size_t>(table)];
    const auto at = std::lower_bound(
        ranges.begin(), ranges.end(), range,
        [](const AddressRange& a, const AddressRange& b) { return a.first < b.first; });
    ranges.insert(at, range);
    std::vector<AddressRange> merged;
    for (const auto& r : ranges) {
        if (!merged.empty() && r.first <= static_cast<std::uint32_t>(merged.back().last) + 1) {
            merged.back().last = std::max(merged.back().last, r.last);
        } else {
            merged.push_back(r);
        }
    }
    ranges = std::move(merged);
}

bool AnsweredRanges::empty() const {
    return std::all_of(tables_.begin(), tables_.end(),
                       [](const auto& ranges) { return ranges.empty(); });
}

bool note_answered(std::span<const std::uint8_t> request, std::span<const std::uint8_t> answer,
                   AnsweredRanges& ranges) {
    const auto decoded = protocol::decode_request(request);
    if (!decoded || answer.empty() || answer[0] != request[0]) return false;
    // A write's answer repeats the first bytes of its request.
    const auto echoes = [&](std::size_t size) {
        return answer.size() == size && request.size() >= size &&
               std::equal(answer.begin(), answer.end(), request.begin());
    };
    const auto carries = [&](std::size_t data) {
        return answer.size() == 2 + data && answer[1] == data;
    };
    using protocol::FunctionCode;
    if (const auto* r = std::get_if<protocol::ReadBitsRequest>(&*decoded)) {
        if (!carries((r->quantity + 7U) / 8U)) return false;
        ranges.add(r->function == FunctionCode::ReadCoils ? Table::Coils : Table::DiscreteInputs,
                   span_of(r->address, r->quantity));
    } else if (const auto* r = std::get_if<protocol::ReadRegistersRequest>(&*decoded)) {
        if (!carries(2U * r->quantity)) return false;
        ranges.add(r->function == FunctionCode::ReadHoldingRegisters ? Table::HoldingRegisters
                                                                     : Table::InputRegisters,
                   span_of(r->address, r->quantity));
    } else if (const auto* r = std::get_if<protocol::WriteSingleCoilRequest>(&*decoded)) {
        if (!echoes(5)) return false;
        ranges.add(Table::Coils, span_of(r->address, 1));
    } else if (const auto* r = std::get_if<protocol::WriteSingleRegisterRequest>(&*decoded)) {
        if (!echoes(5)) return false;
        ranges.add(Table::HoldingRegisters, span_of(r->address, 1));
    } else if (const auto* r = std::get_if<protocol::WriteMultipleCoilsRequest>(&*decoded)) {
        if (!echoes(5)) return false;
        ranges.add(Table::Coils, span_of(r->address, r->quantity));
    } else if (const auto* r = std::get_if<protocol::WriteMultipleRegistersRequest>(&*decoded)) {
        if (!echoes(5)) return false;
        ranges.add(Table::HoldingRegisters, span_of(r->address, r->quantity));
    } else if (const auto* r = std::get_if<protocol::MaskWriteRegisterRequest>(&*decoded)) {
        if (!echoes(7)) return false;
        ranges.add(Table::HoldingRegisters, span_of(r->address, 1));
    } else if (const auto* r =
                   std::get_if<protocol::ReadWriteMultipleRegistersRequest>(&*decoded)) {
        if (!carries(2U * r->read_quantity)) return false;
        ranges.add(Table::HoldingRegisters, span_of(r->read_address, r->read_quantity));
        ranges.add(Table::HoldingRegisters, span_of(r->write_address, r->write_quantity));
    } else {
        return false;
    }
    return true;
}

bool Recon::serves(std::uint8_t function) const {
    return std::find(served.begin(), served.end(), function) != served.end();
}

std::optional<std::vector<std::uint8_t>> probe_request(std::uint8_t function, bool allow_writes) {
    return allow_writes ? conformance::plain_request_pdu(function)
                        : conformance::harmless_request_pdu(function);
}

std::optional<std::string> reconnoitre(const Ask& device, const ReconOptions& options, Recon& out) {
    out.unit = options.unit;
    const Ask ask = [&](std::uint8_t unit, std::span<const std::uint8_t> pdu) {
        auto answer = device(unit, pdu);
        if (answer && unit == options.unit) note_answered(pdu, *answer, out.ranges);
        return answer;
    };
    // The register the liveness check reads, found before any probe so that each probe can be
    // judged by it: a device that answered it before a probe and not after was killed by it.
    std::optional<std::uint16_t> readable;
    if (options.check_address) {
        if (read_answered(ask(options.unit, read_holding(*options.check_address, 1)), 1))
            readable = options.check_address;
    } else {
        for (std::uint16_t address : kProbeAddresses) {
            if (read_answered(ask(options.unit, read_holding(address, 1)), 1)) {
                readable = address;
                break;
            }
        }
    }
    // A second read: one lost answer is not a death.
    const auto still_answers = [&] {
        return read_answered(ask(options.unit, read_holding(*readable, 1)), 1) ||
               read_answered(ask(options.unit, read_holding(*readable, 1)), 1);
    };
    for (std::uint8_t function : conformance::functions_with_plain_requests()) {
        if (options.reads_only && protocol::writes(function)) {
            out.not_asked.push_back(function);
            continue;
        }
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
        if (readable && !still_answers()) {
            out.check_address = *readable;
            out.killed_by = ProbeDeath{function, *request};
            return std::nullopt;
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
