#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <initializer_list>

#include "conformance/plain_requests.hpp"
#include "protocol/function_table.hpp"
#include "protocol/request_template.hpp"
#include "robustness/case_generator.hpp"
#include "robustness/request_bytes.hpp"

// The fixed cases of one frame each: MBAP header fields, sizes, fields of the PDU, function codes,
// sub-functions, file records, unit ids and boundary values.
namespace mblab::robustness {

namespace {

using Bytes = std::vector<std::uint8_t>;

bool is_read(std::uint8_t function) {
    return function >= 0x01 && function <= 0x04;
}

// One past the largest quantity the function's request template allows.
std::uint16_t past_limit(std::uint8_t function,
                         protocol::FieldRole role = protocol::FieldRole::Quantity) {
    return static_cast<std::uint16_t>(
        protocol::field_with(*protocol::find_template(function), role)->max + 1);
}

// Reads of a quantity at an address: past the end of the map (address-wrap) and on its edges
// (boundary).
struct Ranged {
    BadInput kind;
    std::uint8_t function;
    std::uint16_t address;
    std::uint16_t quantity;
};

constexpr std::array<Ranged, 15> kRanged{{
    {BadInput::AddressWrap, 0x01, 0xFFFF, 2},
    {BadInput::AddressWrap, 0x01, 0xFC18, 2000},
    {BadInput::AddressWrap, 0x02, 0xFFFF, 2},
    {BadInput::AddressWrap, 0x03, 0xFFFF, 2},
    {BadInput::AddressWrap, 0x03, 0xFF85, 125},
    {BadInput::AddressWrap, 0x03, 0xFFFF, 125},
    {BadInput::AddressWrap, 0x04, 0xFFFF, 2},
    {BadInput::AddressWrap, 0x04, 0xFF85, 125},
    {BadInput::Boundary, 0x03, 0xFFFE, 1},
    {BadInput::Boundary, 0x03, 0xFFFF, 1},
    {BadInput::Boundary, 0x01, 0x0000, 2000},
    {BadInput::Boundary, 0x01, 0xFFFF, 1},
    {BadInput::Boundary, 0x02, 0x0000, 2000},
    {BadInput::Boundary, 0x04, 0x0000, 125},
    {BadInput::Boundary, 0x18, 0xFFFF, 0},
}};

}  // namespace

void CaseGenerator::add_ranged(BadInput kind) {
    for (const auto& [of, function, address, quantity] : kRanged) {
        if (of != kind) continue;
        Bytes pdu = words(function, {address, quantity});
        // FC 18 names a FIFO address alone.
        if (function == 0x18) pdu.resize(3);
        add_frame(
            kind,
            fmt::format("FC 0x{:02X} address 0x{:04X} quantity {}", function, address, quantity),
            pdu);
    }
}

void CaseGenerator::fixed_frames() {
    const std::uint8_t unit = recon_.unit;
    const std::uint16_t check = recon_.check_address;
    const std::uint16_t w = write_address_;
    const Bytes read = words(0x03, {check, 1});

    for (std::uint16_t protocol : {0x0001, 0x0002, 0x00FF, 0x8000, 0xFFFF}) {
        FuzzCase c{BadInput::ProtocolId, fmt::format("protocol id 0x{:04X}", protocol), {}, false};
        c.steps.push_back({0, mbap_frame(next_transaction(), unit, read, protocol), {}});
        add(std::move(c));
    }

    for (std::uint16_t length : {0, 1, 2, 3, 5, 7, 8, 12, 253, 254, 255, 256, 0x7FFF, 0xFFFF}) {
        FuzzCase c{
            BadInput::MbapLength, fmt::format("MBAP length {} for 6 bytes", length), {}, false};
        c.steps.push_back({0, mbap_frame(next_transaction(), unit, read, 0, length), {}});
        add(std::move(c));
    }
    {
        // Short by two, then a valid request: a device that loses step answers neither right.
        FuzzCase c{
            BadInput::MbapLength, "MBAP length 4 for 6 bytes, then a valid request", {}, false};
        Bytes both = mbap_frame(next_transaction(), unit, read, 0, 4);
        const Bytes valid = mbap_frame(next_transaction(), unit, read);
        both.insert(both.end(), valid.begin(), valid.end());
        c.steps.push_back({0, std::move(both), {}});
        add(std::move(c));
    }

    for (std::size_t size : {253, 254, 260, 300, 1024, 4096}) {
        Bytes pdu = read;
        pdu.resize(size, 0);
        FuzzCase c{BadInput::Oversize, fmt::format("PDU of {} bytes", size), {}, false};
        const auto length = static_cast<std::uint16_t>(std::min<std::size_t>(size + 1, 0xFFFF));
        c.steps.push_back({0, mbap_frame(next_transaction(), unit, pdu, 0, length), {}});
        add(std::move(c));
    }
    {
        const auto over = past_limit(0x10);  // one register more than a PDU holds
        const auto count = byte_count_for(0x10, over);
        add_frame(BadInput::Oversize,
                  fmt::format("FC 0x10 of {} registers (PDU {} bytes)", over, 6 + count),
                  multiple_write(0x10, w, over, count, count));
    }

    // Every public code, served or not: many stacks parse a request before they dispatch it, so
    // a code answered with exception 01 may still read past a short frame.
    for (std::uint8_t function : conformance::functions_with_plain_requests()) {
        add_frame(BadInput::Truncated, fmt::format("FC 0x{:02X} alone", function), Bytes{function});
        auto whole = probe_request(function, true);
        if (!whole || whole->size() < 3) continue;
        // A write is aimed at the writable range; file records have no address there.
        if (const auto* address = protocol::field_with(*protocol::find_template(function),
                                                       protocol::FieldRole::Address);
            address != nullptr && protocol::writes(function)) {
            protocol::write_field(*whole, *address, w);
        }
        for (std::size_t keep : {std::size_t{2}, whole->size() - 1}) {
            const Bytes cut(whole->begin(), whole->begin() + static_cast<long>(keep));
            add_frame(BadInput::Truncated,
                      fmt::format("FC 0x{:02X} cut to {} bytes", function, cut.size()), cut);
        }
    }

    // Each quantity at 0, one past its limit ([APP] 6, from the request template) and 0xFFFF.
    // Served or not, as above.
    for (std::uint8_t function : {0x01, 0x02, 0x03, 0x04, 0x0F, 0x10}) {
        for (std::uint16_t quantity :
             {std::uint16_t{0}, past_limit(function), std::uint16_t{0xFFFF}}) {
            const std::string name = fmt::format("FC 0x{:02X} quantity {}", function, quantity);
            if (is_read(function)) {
                add_frame(BadInput::Quantity, name, words(function, {check, quantity}));
            } else {
                const auto count = byte_count_for(function, quantity);
                add_frame(BadInput::Quantity, name,
                          multiple_write(function, w, quantity, count, count));
            }
        }
    }
    {
        const auto read_over = past_limit(0x17, protocol::FieldRole::ReadQuantity);
        const auto write_over = past_limit(0x17);
        add_frame(BadInput::Quantity, "FC 0x17 read quantity 0", read_write(check, 0, w, 1, 2, 2));
        add_frame(BadInput::Quantity, fmt::format("FC 0x17 read quantity {}", read_over),
                  read_write(check, read_over, w, 1, 2, 2));
        const auto count = byte_count_for(0x17, write_over);
        add_frame(BadInput::Quantity, fmt::format("FC 0x17 write quantity {}", write_over),
                  read_write(check, 1, w, write_over, count, count));
    }

    struct Count {
        std::uint16_t quantity;
        std::uint8_t byte_count;
        std::size_t data;
    };
    for (auto [quantity, count, data] :
         {Count{1, 0, 2}, Count{1, 1, 2}, Count{1, 3, 2}, Count{1, 4, 4}, Count{1, 0xFF, 2},
          Count{2, 2, 2}, Count{1, 2, 0}, Count{2, 0xFF, 0xFF}}) {
        add_frame(BadInput::ByteCount,
                  fmt::format("FC 0x10 byte count {} for {} registers, {} data bytes", count,
                              quantity, data),
                  multiple_write(0x10, w, quantity, count, data));
    }
    for (auto [quantity, count, data] :
         {Count{8, 0, 1}, Count{8, 2, 1}, Count{9, 1, 1}, Count{1, 0xFF, 1}, Count{1, 1, 0}}) {
        add_frame(
            BadInput::ByteCount,
            fmt::format("FC 0x0F byte count {} for {} coils, {} data bytes", count, quantity, data),
            multiple_write(0x0F, w, quantity, count, data));
    }
    for (auto [quantity, count, data] : {Count{1, 0, 2}, Count{1, 3, 2}, Count{1, 0xFF, 2}}) {
        add_frame(BadInput::ByteCount,
                  fmt::format("FC 0x17 byte count {} for {} written registers", count, quantity),
                  read_write(check, 1, w, quantity, count, data));
    }

    add_ranged(BadInput::AddressWrap);
    add_frame(BadInput::AddressWrap, "FC 0x17 write range 0xFFFF + 2",
              read_write(check, 1, 0xFFFF, 2, 4, 4));
    add_frame(BadInput::AddressWrap, "FC 0x10 address 0xFFFF quantity 2",
              multiple_write(0x10, 0xFFFF, 2, 4, 4));
    add_frame(BadInput::AddressWrap, "FC 0x0F address 0xFFFF quantity 16",
              multiple_write(0x0F, 0xFFFF, 16, 2, 2));

    // The codes a fuzzer should try first, then every other code without a row.
    std::vector<std::uint8_t> unknown = {0x00, 0x7F, 0x80, 0xFF, 0x41, 0x42, 0x43, 0x44, 0x45,
                                         0x46, 0x47, 0x48, 0x64, 0x65, 0x66, 0x67, 0x68, 0x69,
                                         0x6A, 0x6B, 0x6C, 0x6D, 0x6E, 0x83, 0x90};
    for (unsigned code = 0; code <= 0xFF; ++code) {
        const auto function = static_cast<std::uint8_t>(code);
        if (protocol::find_function(function) == nullptr &&
            std::find(unknown.begin(), unknown.end(), function) == unknown.end())
            unknown.push_back(function);
    }
    for (std::uint8_t function : unknown) {
        if (protocol::find_function(function) != nullptr) continue;
        add_frame(BadInput::UnknownFunction, fmt::format("FC 0x{:02X}", function),
                  Bytes{function, 0x00, 0x00, 0x00, 0x01});
    }

    for (std::uint16_t sub :
         {0x0000, 0x0002, 0x000A, 0x000B, 0x000C, 0x000D, 0x000E, 0x000F, 0x0010, 0x0011, 0x0012,
          0x0013, 0x0014, 0x0015, 0x0016, 0x00FF, 0x8000, 0xFFFF, 0x0001, 0x0003, 0x0004}) {
        add_frame(BadInput::SubFunction, fmt::format("FC 0x08 sub-function 0x{:04X}", sub),
                  words(0x08, {sub, 0x0000}));
    }
    add_frame(BadInput::SubFunction, "FC 0x08 sub-function 0x0000 without data",
              words(0x08, {0x0000}));
    add_frame(BadInput::SubFunction, "FC 0x08 echo of 250 bytes", [] {
        Bytes pdu = words(0x08, {0x0000});
        pdu.resize(253, 0xA5);
        return pdu;
    }());
    for (std::uint8_t mei : {0x00, 0x0D, 0x0F, 0x7F, 0xFF}) {
        add_frame(BadInput::SubFunction, fmt::format("FC 0x2B MEI type 0x{:02X}", mei),
                  Bytes{0x2B, mei, 0x01, 0x00});
    }
    for (std::uint8_t code : {0x00, 0x05, 0xFF}) {
        add_frame(BadInput::SubFunction, fmt::format("FC 0x2B/0E read code 0x{:02X}", code),
                  Bytes{0x2B, 0x0E, code, 0x00});
    }
    for (std::uint8_t object : {0x07, 0x7F, 0x80, 0xFF}) {
        add_frame(BadInput::SubFunction, fmt::format("FC 0x2B/0E object 0x{:02X}", object),
                  Bytes{0x2B, 0x0E, 0x04, object});
        add_frame(BadInput::SubFunction,
                  fmt::format("FC 0x2B/0E stream from object 0x{:02X}", object),
                  Bytes{0x2B, 0x0E, 0x03, object});
    }
    add_frame(BadInput::SubFunction, "FC 0x2B/0E without read code", Bytes{0x2B, 0x0E});

    const std::initializer_list<std::pair<const char*, Bytes>> file_records = {
        {"byte count 0x07, sub-request cut", {0x14, 0x07, 0x06, 0x00, 0x01, 0x00, 0x00}},
        {"byte count 0xFF for one sub-request",
         {0x14, 0xFF, 0x06, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01}},
        {"byte count 0", {0x14, 0x00}},
        {"byte count 0x06", {0x14, 0x06, 0x06, 0x00, 0x01, 0x00, 0x00, 0x00}},
        {"record 10000", {0x14, 0x07, 0x06, 0x00, 0x01, 0x27, 0x10, 0x00, 0x01}},
        {"reference type 7", {0x14, 0x07, 0x07, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01}},
        {"file 0", {0x14, 0x07, 0x06, 0x00, 0x00, 0x00, 0x00, 0x00, 0x01}},
        {"record length 0xFFFF", {0x14, 0x07, 0x06, 0x00, 0x01, 0x00, 0x00, 0xFF, 0xFF}},
        {"second sub-request cut",
         {0x14, 0x0E, 0x06, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x06, 0x00, 0x01}},
        {"write, record data past the frame",
         {0x15, 0x09, 0x06, 0x00, 0x01, 0x00, 0x00, 0x00, 0x7D, 0x00, 0x00}},
    };
    for (const auto& [name, pdu] : file_records)
        add_frame(BadInput::FileRecord, fmt::format("FC 0x{:02X} {}", pdu[0], name), pdu);

    for (unsigned id = 0; id <= 0xFF; ++id) {
        if (id == unit) continue;
        FuzzCase c{BadInput::UnitId, fmt::format("unit id {}", id), {}, false};
        c.steps.push_back(
            {0, mbap_frame(next_transaction(), static_cast<std::uint8_t>(id), read), {}});
        add(std::move(c));
    }

    for (std::uint16_t transaction : {0x0000, 0xFFFF, 0x8000}) {
        FuzzCase c{
            BadInput::Boundary, fmt::format("transaction id 0x{:04X}", transaction), {}, false};
        c.steps.push_back({0, mbap_frame(transaction, unit, read), {}});
        add(std::move(c));
    }
    const auto max_read = recon_.max_read;
    for (std::uint16_t quantity : {std::uint16_t{1}, max_read,
                                   static_cast<std::uint16_t>(max_read + 1), std::uint16_t{125}}) {
        add_frame(BadInput::Boundary, fmt::format("FC 0x03 quantity {}", quantity),
                  words(0x03, {check, quantity}));
    }
    add_ranged(BadInput::Boundary);
    for (std::uint16_t value : {0x0000, 0xFF00, 0xFF01, 0x00FF, 0xFFFF}) {
        add_frame(BadInput::Boundary, fmt::format("FC 0x05 value 0x{:04X}", value),
                  words(0x05, {w, value}));
    }
    for (std::uint16_t value : {0x0000, 0xFFFF}) {
        add_frame(BadInput::Boundary, fmt::format("FC 0x06 value 0x{:04X}", value),
                  words(0x06, {w, value}));
        add_frame(BadInput::Boundary, fmt::format("FC 0x16 masks 0x{:04X}", value),
                  words(0x16, {w, value, value}));
    }
}

}  // namespace mblab::robustness
