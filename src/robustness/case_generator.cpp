#include "robustness/case_generator.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <initializer_list>

#include "protocol/function_table.hpp"
#include "robustness/in_turn.hpp"
#include "robustness/line_cases.hpp"
#include "robustness/pairwise_cases.hpp"
#include "robustness/request_bytes.hpp"

namespace mblab::robustness {

namespace {

using Bytes = std::vector<std::uint8_t>;

std::uint16_t field16(std::span<const std::uint8_t> pdu, std::size_t at) {
    return static_cast<std::uint16_t>(pdu[at] << 8 | pdu[at + 1]);
}

bool is_read(std::uint8_t function) {
    return function >= 0x01 && function <= 0x04;
}

}  // namespace

bool may_send(std::span<const std::uint8_t> pdu, const WritePolicy& policy) {
    if (pdu.empty() || policy.allow_writes) return true;
    const std::uint8_t function = pdu[0];
    if (function == 0x08) {
        if (pdu.size() < 3) return true;
        const auto sub = field16(pdu, 1);
        return sub != 0x01 && sub != 0x03 && sub != 0x04;
    }
    const auto* row = protocol::find_function(function);
    if (row == nullptr || row->writes == protocol::Writes::No) return true;
    if (!policy.writable || function == 0x15) return false;
    // The address and quantity the request names; what is cut off names nothing.
    std::size_t at = 1;
    std::size_t quantity_at = 3;
    bool has_quantity = function == 0x0F || function == 0x10;
    if (function == 0x17) {
        at = 5;
        quantity_at = 7;
        has_quantity = true;
    }
    if (pdu.size() < at + 2) return true;
    const std::uint32_t address = field16(pdu, at);
    std::uint32_t quantity = 1;
    if (has_quantity && pdu.size() >= quantity_at + 2)
        quantity = std::max<std::uint32_t>(field16(pdu, quantity_at), 1);
    const std::uint32_t start = policy.writable->start;
    return address >= start && address + quantity <= start + policy.writable->count;
}

CaseGenerator::CaseGenerator(Recon recon, WritePolicy policy, std::uint64_t seed,
                             protocol::Framing framing, std::chrono::milliseconds gap,
                             ResourceLimits limits)
    : recon_(std::move(recon)),
      policy_(policy),
      framing_(framing),
      limits_(limits),
      prng_(seed),
      by_class_(kBadInputCount) {
    write_address_ = policy_.writable ? policy_.writable->start : 0;
    fixed_frames();
    fixed_streams();
    resource_cases();
    pairwise();
    if (framing_ != protocol::Framing::Mbap) {
        for (auto& cases : by_class_) {
            std::vector<FuzzCase> kept;
            for (const auto& c : cases) {
                if (auto framed = on_line(c, framing_)) kept.push_back(std::move(*framed));
            }
            cases = std::move(kept);
        }
        for (auto& c : line_cases(framing_, recon_.unit, recon_.check_address, gap))
            add(std::move(c));
    }
    // A class at a time in turn, so that a short budget reaches every class.
    fixed_ = in_turn(std::move(by_class_));
    by_class_.clear();
}

void CaseGenerator::add(FuzzCase c) {
    by_class_[static_cast<std::size_t>(c.kind)].push_back(std::move(c));
}

bool CaseGenerator::withhold(BadInput kind, std::span<const std::uint8_t> pdu) {
    if (may_send(pdu, policy_)) return false;
    withheld_.resize(kBadInputCount);
    ++withheld_[static_cast<std::size_t>(kind)];
    return true;
}

void CaseGenerator::add_frame(BadInput kind, std::string name, std::span<const std::uint8_t> pdu) {
    if (withhold(kind, pdu)) return;
    FuzzCase c{kind, std::move(name), {}, false};
    c.steps.push_back({0, mbap_frame(next_transaction(), recon_.unit, pdu), {}});
    add(std::move(c));
}

void CaseGenerator::pairwise() {
    // On a line the MBAP fields are no parameters: each row is a frame that re-frames whole.
    for (auto& frame :
         pairwise_frames(recon_, policy_.writable, framing_ == protocol::Framing::Mbap)) {
        if (withhold(BadInput::Pairwise, frame.pdu)) continue;
        FuzzCase c{BadInput::Pairwise, std::move(frame.name), {}, false};
        c.steps.push_back({0,
                           mbap_frame(frame.transaction.value_or(next_transaction()), frame.unit,
                                      frame.pdu, frame.protocol, frame.length),
                           {}});
        add(std::move(c));
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
    add_frame(BadInput::Oversize, "FC 0x10 of 124 registers (PDU 254 bytes)",
              multiple_write(0x10, w, 124, 248, 248));

    for (std::uint8_t function : recon_.served) {
        add_frame(BadInput::Truncated, fmt::format("FC 0x{:02X} alone", function), Bytes{function});
        auto whole = probe_request(function, true);
        if (!whole || whole->size() < 3) continue;
        if (const auto* row = protocol::find_function(function);
            row != nullptr && row->writes == protocol::Writes::Yes) {
            // Aimed at the writable range; file records have no address there.
            const std::size_t at = function == 0x17 ? 5 : 1;
            if (function != 0x15) {
                (*whole)[at] = static_cast<std::uint8_t>(w >> 8);
                (*whole)[at + 1] = static_cast<std::uint8_t>(w);
            }
        }
        for (std::size_t keep : {std::size_t{2}, whole->size() - 1}) {
            const Bytes cut(whole->begin(), whole->begin() + static_cast<long>(keep));
            add_frame(BadInput::Truncated,
                      fmt::format("FC 0x{:02X} cut to {} bytes", function, cut.size()), cut);
        }
    }

    struct Limit {
        std::uint8_t function;
        std::uint16_t over;
    };
    for (auto [function, over] : {Limit{0x01, 2001}, Limit{0x02, 2001}, Limit{0x03, 126},
                                  Limit{0x04, 126}, Limit{0x0F, 1969}, Limit{0x10, 124}}) {
        if (!recon_.serves(function)) continue;
        for (std::uint16_t quantity : {std::uint16_t{0}, over, std::uint16_t{0xFFFF}}) {
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
    if (recon_.serves(0x17)) {
        add_frame(BadInput::Quantity, "FC 0x17 read quantity 0", read_write(check, 0, w, 1, 2, 2));
        add_frame(BadInput::Quantity, "FC 0x17 read quantity 126",
                  read_write(check, 126, w, 1, 2, 2));
        add_frame(BadInput::Quantity, "FC 0x17 write quantity 122",
                  read_write(check, 1, w, 122, 244, 244));
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

    for (auto [function, address, quantity] :
         std::initializer_list<std::tuple<std::uint8_t, std::uint16_t, std::uint16_t>>{
             {0x01, 0xFFFF, 2},
             {0x01, 0xFC18, 2000},
             {0x02, 0xFFFF, 2},
             {0x03, 0xFFFF, 2},
             {0x03, 0xFF85, 125},
             {0x03, 0xFFFF, 125},
             {0x04, 0xFFFF, 2},
             {0x04, 0xFF85, 125}}) {
        add_frame(
            BadInput::AddressWrap,
            fmt::format("FC 0x{:02X} address 0x{:04X} quantity {}", function, address, quantity),
            words(function, {address, quantity}));
    }
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
    for (auto [function, address, quantity] :
         std::initializer_list<std::tuple<std::uint8_t, std::uint16_t, std::uint16_t>>{
             {0x03, 0xFFFE, 1},
             {0x03, 0xFFFF, 1},
             {0x01, 0x0000, 2000},
             {0x01, 0xFFFF, 1},
             {0x02, 0x0000, 2000},
             {0x04, 0x0000, 125},
             {0x18, 0xFFFF, 0}}) {
        Bytes pdu = words(function, {address, quantity});
        if (function == 0x18) pdu.resize(3);
        add_frame(
            BadInput::Boundary,
            fmt::format("FC 0x{:02X} address 0x{:04X} quantity {}", function, address, quantity),
            pdu);
    }
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

void CaseGenerator::fixed_streams() {
    const std::uint8_t unit = recon_.unit;
    const Bytes read = words(0x03, {recon_.check_address, 1});
    using std::chrono::milliseconds;

    {
        FuzzCase c{BadInput::SplitFrame, "a request a byte at a time, 5 ms apart", {}, false};
        for (std::uint8_t byte : mbap_frame(next_transaction(), unit, read))
            c.steps.push_back({0, {byte}, milliseconds(5)});
        add(std::move(c));
    }
    for (auto [cut, pause] : {std::pair{std::size_t{7}, 50}, std::pair{std::size_t{3}, 200},
                              std::pair{std::size_t{1}, 500}, std::pair{std::size_t{10}, 100}}) {
        const Bytes frame = mbap_frame(next_transaction(), unit, read);
        FuzzCase c{BadInput::SplitFrame,
                   fmt::format("a request cut after {} bytes, {} ms apart", cut, pause),
                   {},
                   false};
        c.steps.push_back(
            {0, Bytes(frame.begin(), frame.begin() + static_cast<long>(cut)), milliseconds(pause)});
        c.steps.push_back({0, Bytes(frame.begin() + static_cast<long>(cut), frame.end()), {}});
        add(std::move(c));
    }
    {
        Bytes first = mbap_frame(next_transaction(), unit, read);
        const Bytes second = mbap_frame(next_transaction(), unit, read);
        first.insert(first.end(), second.begin(), second.begin() + 4);
        FuzzCase c{BadInput::SplitFrame, "two requests cut inside the second's header", {}, false};
        c.steps.push_back({0, std::move(first), milliseconds(20)});
        c.steps.push_back({0, Bytes(second.begin() + 4, second.end()), {}});
        add(std::move(c));
    }

    for (std::size_t keep = 1; keep <= 7; ++keep) {
        const Bytes frame = mbap_frame(next_transaction(), unit, read);
        FuzzCase c{BadInput::PartialHeader,
                   fmt::format("{} of {} bytes, left hanging", keep, frame.size()),
                   {},
                   true};
        c.steps.push_back({0, Bytes(frame.begin(), frame.begin() + static_cast<long>(keep)), {}});
        add(std::move(c));
    }

    for (std::size_t count : {2, 10, 50, 200}) {
        FuzzCase c{
            BadInput::Pipelined, fmt::format("{} requests in one segment", count), {}, false};
        Bytes all;
        for (std::size_t i = 0; i < count; ++i) {
            const Bytes frame = mbap_frame(next_transaction(), unit, read);
            all.insert(all.end(), frame.begin(), frame.end());
        }
        c.steps.push_back({0, std::move(all), {}});
        add(std::move(c));
    }
    {
        FuzzCase c{BadInput::Pipelined,
                   "30 requests, valid, unknown and protocol id 1 in turn",
                   {},
                   false};
        Bytes all;
        const Bytes unknown{0x41, 0x00, 0x00};
        for (std::size_t i = 0; i < 10; ++i) {
            for (const Bytes& frame : {mbap_frame(next_transaction(), unit, read),
                                       mbap_frame(next_transaction(), unit, unknown),
                                       mbap_frame(next_transaction(), unit, read, 1)})
                all.insert(all.end(), frame.begin(), frame.end());
        }
        c.steps.push_back({0, std::move(all), {}});
        add(std::move(c));
    }
    {
        FuzzCase c{BadInput::Pipelined, "50 requests with one transaction id", {}, false};
        Bytes all;
        const Bytes frame = mbap_frame(next_transaction(), unit, read);
        for (std::size_t i = 0; i < 50; ++i)
            all.insert(all.end(), frame.begin(), frame.end());
        c.steps.push_back({0, std::move(all), {}});
        add(std::move(c));
    }

    for (std::size_t count : {10, 50, 100}) {
        FuzzCase c{BadInput::ManyConnections,
                   fmt::format("{} connections, a request on each", count),
                   {},
                   false};
        for (std::size_t i = 0; i < count; ++i)
            c.steps.push_back({i, mbap_frame(next_transaction(), unit, read), {}});
        add(std::move(c));
    }
    {
        FuzzCase c{BadInput::ManyConnections, "20 connections, half a header on each", {}, true};
        for (std::size_t i = 0; i < 20; ++i) {
            const Bytes frame = mbap_frame(next_transaction(), unit, read);
            c.steps.push_back({i, Bytes(frame.begin(), frame.begin() + 3), {}});
        }
        add(std::move(c));
    }
}

void CaseGenerator::resource_cases() {
    const std::uint8_t unit = recon_.unit;
    const Bytes read = words(0x03, {recon_.check_address, 1});
    const Bytes largest = words(0x03, {recon_.check_address, recon_.max_read});
    auto requests = [&](std::size_t count, const Bytes& pdu) {
        Bytes all;
        all.reserve(count * (7 + pdu.size()));
        for (std::size_t i = 0; i < count; ++i) {
            const Bytes frame = mbap_frame(next_transaction(), unit, pdu);
            all.insert(all.end(), frame.begin(), frame.end());
        }
        return all;
    };

    if (limits_.connections > 100) {
        // Idle connections held through the check: a device that is full must close the
        // oldest idle one for a newcomer [TCPG 4.2.1.1], not refuse the newcomer.
        FuzzCase c{BadInput::ManyConnections,
                   fmt::format("{} connections, a request on each, held open", limits_.connections),
                   {},
                   true};
        for (std::size_t i = 0; i < limits_.connections; ++i)
            c.steps.push_back({i, mbap_frame(next_transaction(), unit, read), {}});
        add(std::move(c));
    }

    // The answers to the largest read pile up unread: megabytes a device must not buffer.
    for (auto [connections, count] : {std::pair{std::size_t{1}, std::size_t{40000}},
                                      std::pair{std::size_t{8}, std::size_t{4000}}}) {
        FuzzCase c{BadInput::SlowReader,
                   fmt::format("{} connection(s), {} FC 03 reads of {} each, answers never read",
                               connections, count, recon_.max_read),
                   {},
                   true};
        for (std::size_t i = 0; i < connections; ++i) {
            c.steps.push_back({i, requests(count, largest), {}});
            c.steps.back().unread = true;
        }
        // Time for the device to work through the requests until its send buffer is full: a
        // device that stalls on a slow reader does so only once it is.
        c.steps.back().pause = std::chrono::milliseconds(500);
        add(std::move(c));
    }

    if (limits_.half_open) {
        for (auto [connections, keep] : {std::pair{std::size_t{20}, std::size_t{3}},
                                         std::pair{std::size_t{300}, std::size_t{7}}}) {
            FuzzCase c{BadInput::HalfOpen,
                       fmt::format("{} connections, {} bytes of a request, then gone without a FIN",
                                   connections, keep),
                       {},
                       false};
            for (std::size_t i = 0; i < connections; ++i) {
                const Bytes frame = mbap_frame(next_transaction(), unit, read);
                c.steps.push_back(
                    {i, Bytes(frame.begin(), frame.begin() + static_cast<long>(keep)), {}});
                c.steps.back().vanish = true;
            }
            add(std::move(c));
        }
    }

    {
        FuzzCase c{BadInput::Flood, "20000 reads streamed, answers read as they come", {}, false};
        c.steps.push_back({0, requests(20000, read), {}});
        add(std::move(c));
    }
    const Bytes write_probe = words(0x06, {write_address_, 1});
    if (recon_.serves(0x06) && !withhold(BadInput::Flood, write_probe)) {
        FuzzCase c{BadInput::Flood,
                   fmt::format("20000 requests streamed, FC 06 of 1..10000 to register {} between "
                               "reads; the last acknowledged value read back",
                               write_address_),
                   {},
                   false};
        Bytes all;
        for (std::uint16_t value = 1; value <= 10000; ++value) {
            for (const Bytes& frame :
                 {mbap_frame(next_transaction(), unit, words(0x06, {write_address_, value})),
                  mbap_frame(next_transaction(), unit, read)})
                all.insert(all.end(), frame.begin(), frame.end());
        }
        c.steps.push_back({0, std::move(all), {}});
        c.ledger = WriteLedger{write_address_};
        add(std::move(c));
    }
}

FuzzCase CaseGenerator::next() {
    if (taken_ < fixed_.size()) return fixed_[taken_++];
    ++taken_;
    if (framing_ == protocol::Framing::Mbap) return mutation();
    // A mutation of the MBAP header alone has nothing to say on a line: another is drawn.
    while (true) {
        if (auto framed = on_line(mutation(), framing_)) return std::move(*framed);
    }
}

FuzzCase CaseGenerator::mutation() {
    // The valid requests mutations start from: reads of what answers, and the plain requests of
    // the served functions that the policy lets through.
    std::vector<Bytes> bases = {words(0x03, {recon_.check_address, 1}),
                                words(0x03, {recon_.check_address, recon_.max_read})};
    for (std::uint8_t function : recon_.served) {
        if (auto pdu = probe_request(function, true); pdu && may_send(*pdu, policy_))
            bases.push_back(*pdu);
        if (auto safe = probe_request(function, false)) bases.push_back(*safe);
    }
    auto pick = [&](std::size_t n) { return static_cast<std::size_t>(prng_.next() % n); };
    static constexpr std::array<std::uint8_t, 8> kBoundaryBytes{0x00, 0x01, 0x7F, 0x80,
                                                                0xFE, 0xFF, 0x10, 0x7D};
    for (int attempt = 0;; ++attempt) {
        Bytes pdu = bases[pick(bases.size())];
        std::string what;
        const std::size_t changes = 1 + pick(3);
        for (std::size_t i = 0; i < changes; ++i) {
            const std::size_t at = pdu.empty() ? 0 : pick(pdu.size());
            switch (pick(7)) {
                case 0:
                    if (pdu.empty()) break;
                    pdu[at] ^= static_cast<std::uint8_t>(1U << pick(8));
                    what += fmt::format(" flip@{}", at);
                    break;
                case 1:
                    if (pdu.empty()) break;
                    pdu[at] = kBoundaryBytes[pick(kBoundaryBytes.size())];
                    what += fmt::format(" set@{}={:02X}", at, pdu[at]);
                    break;
                case 2:
                    pdu.insert(pdu.begin() + static_cast<long>(at),
                               static_cast<std::uint8_t>(prng_.next()));
                    what += fmt::format(" insert@{}", at);
                    break;
                case 3:
                    if (pdu.size() < 2) break;
                    pdu.erase(pdu.begin() + static_cast<long>(at));
                    what += fmt::format(" delete@{}", at);
                    break;
                case 4:
                    if (pdu.size() < 2) break;
                    pdu.resize(1 + pick(pdu.size() - 1));
                    what += fmt::format(" cut@{}", pdu.size());
                    break;
                case 5: {
                    const std::size_t extra = 1 + pick(8);
                    for (std::size_t k = 0; k < extra; ++k)
                        pdu.push_back(static_cast<std::uint8_t>(prng_.next()));
                    what += fmt::format(" append{}", extra);
                    break;
                }
                default:
                    if (pdu.size() < 3) break;
                    pdu[at == 0 ? 1 : at] = 0xFF;
                    if (at + 1 < pdu.size()) pdu[at + 1] = 0xFF;
                    what += fmt::format(" ffff@{}", at == 0 ? 1 : at);
                    break;
            }
        }
        if (pdu.empty() || (!may_send(pdu, policy_) && attempt < 50)) continue;
        if (!may_send(pdu, policy_)) pdu = bases.front();
        std::optional<std::uint16_t> length;
        std::uint16_t protocol = 0;
        std::uint8_t unit = recon_.unit;
        // Mostly a correct header, so the PDU is what is tested; sometimes the header too.
        switch (pick(10)) {
            case 0:
                length = static_cast<std::uint16_t>(pdu.size() + 1 + pick(5) - 2);
                what += fmt::format(" length={}", *length);
                break;
            case 1:
                unit = static_cast<std::uint8_t>(prng_.next());
                what += fmt::format(" unit={}", unit);
                break;
            case 2:
                protocol = static_cast<std::uint16_t>(prng_.next());
                what += fmt::format(" protocol={:04X}", protocol);
                break;
            default:
                break;
        }
        FuzzCase c{BadInput::Mutation,
                   fmt::format("mutation {}: FC 0x{:02X}{}", taken_ - fixed_.size(), pdu[0], what),
                   {},
                   false};
        c.steps.push_back({0, mbap_frame(next_transaction(), unit, pdu, protocol, length), {}});
        return c;
    }
}

}  // namespace mblab::robustness
