#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <string_view>

#include "protocol/function_code.hpp"

// One row per public function code: every fact about a code that is not its codec. Names, RTU
// length prediction, is_public_function and the reference device's rules all read these rows, so
// a code is added in one place (docs/adding-a-function-code.md lists the rest: codec, device,
// catalogue).
namespace mblab::protocol {

// How a PDU's size is found ([APP] section 6). RTU frames carry no length field, so a serial
// receiver predicts the frame's end from these.
enum class PduShape : std::uint8_t {
    Unknown,           // only silence (t3.5) tells
    Fixed,             // `value` bytes
    Count8,            // a byte count at PDU offset `value` gives the bytes after it
    Count16,           // the same with a two-byte count
    Diagnostics,       // FC 08: by sub-function
    DeviceIdRequest,   // FC 2B: MEI 0E is fixed, other MEI types are Unknown
    DeviceIdResponse,  // FC 2B/0E: by walking the objects
};

struct PduLayout {
    PduShape shape = PduShape::Unknown;
    std::uint8_t value = 0;

    friend constexpr bool operator==(const PduLayout&, const PduLayout&) = default;
};

constexpr PduLayout fixed_pdu(std::uint8_t size) {
    return {PduShape::Fixed, size};
}
constexpr PduLayout count_at(std::uint8_t offset) {
    return {PduShape::Count8, offset};
}
constexpr PduLayout count16_at(std::uint8_t offset) {
    return {PduShape::Count16, offset};
}
// A shape with its own rule in rtu_frame_length.cpp (FC 08, FC 2B).
constexpr PduLayout shaped(PduShape shape) {
    return {shape, 0};
}

// What a unit does with a request to serial address 0.
enum class Broadcast : std::uint8_t {
    Ignore,   // INSTR 5.7.1: reads and self-diagnostics do not run on broadcast
    Execute,  // [SER]: a broadcast carries a write
};

// Whether the request changes what a state file keeps (coils, holding registers, file records).
enum class Writes : std::uint8_t { No, Yes };

// Whether a completed request adds one to the FC 0B event counter ([APP] 6.9).
enum class EventCounting : std::uint8_t {
    Counts,
    Never,          // reading the counter or the log is not itself an event
    BySubFunction,  // FC 08: every sub-function but those that reset the counter
};

// Which data addresses a request names, for fault rules with an address filter.
enum class AddressScope : std::uint8_t {
    None,
    Range,      // the message's address and quantity
    Single,     // the message's address
    ReadWrite,  // FC 17: from the lower start to the higher end of its read and write ranges
};

struct FunctionRow {
    FunctionCode code{};
    std::string_view name;
    PduLayout request;
    PduLayout response;
    Broadcast broadcast = Broadcast::Ignore;
    Writes writes = Writes::No;
    EventCounting events = EventCounting::Counts;
    AddressScope scope = AddressScope::None;
};

// Sorted by code. Columns: code, name, request layout, response layout, broadcast, writes,
// event counting, address scope.
inline constexpr FunctionRow kFunctionTable[] = {
    {FunctionCode::ReadCoils, "read coils", fixed_pdu(5), count_at(1), Broadcast::Ignore,
     Writes::No, EventCounting::Counts, AddressScope::Range},
    {FunctionCode::ReadDiscreteInputs, "read discrete inputs", fixed_pdu(5), count_at(1),
     Broadcast::Ignore, Writes::No, EventCounting::Counts, AddressScope::Range},
    {FunctionCode::ReadHoldingRegisters, "read holding registers", fixed_pdu(5), count_at(1),
     Broadcast::Ignore, Writes::No, EventCounting::Counts, AddressScope::Range},
    {FunctionCode::ReadInputRegisters, "read input registers", fixed_pdu(5), count_at(1),
     Broadcast::Ignore, Writes::No, EventCounting::Counts, AddressScope::Range},
    {FunctionCode::WriteSingleCoil, "write single coil", fixed_pdu(5), fixed_pdu(5),
     Broadcast::Execute, Writes::Yes, EventCounting::Counts, AddressScope::Single},
    {FunctionCode::WriteSingleRegister, "write single register", fixed_pdu(5), fixed_pdu(5),
     Broadcast::Execute, Writes::Yes, EventCounting::Counts, AddressScope::Single},
    {FunctionCode::ReadExceptionStatus, "read exception status", fixed_pdu(1), fixed_pdu(2),
     Broadcast::Ignore, Writes::No, EventCounting::Counts, AddressScope::None},
    {FunctionCode::Diagnostics, "diagnostics", shaped(PduShape::Diagnostics),
     shaped(PduShape::Diagnostics), Broadcast::Ignore, Writes::No, EventCounting::BySubFunction,
     AddressScope::None},
    {FunctionCode::GetCommEventCounter, "get comm event counter", fixed_pdu(1), fixed_pdu(5),
     Broadcast::Ignore, Writes::No, EventCounting::Never, AddressScope::None},
    {FunctionCode::GetCommEventLog, "get comm event log", fixed_pdu(1), count_at(1),
     Broadcast::Ignore, Writes::No, EventCounting::Never, AddressScope::None},
    {FunctionCode::WriteMultipleCoils, "write multiple coils", count_at(5), fixed_pdu(5),
     Broadcast::Execute, Writes::Yes, EventCounting::Counts, AddressScope::Range},
    {FunctionCode::WriteMultipleRegisters, "write multiple registers", count_at(5), fixed_pdu(5),
     Broadcast::Execute, Writes::Yes, EventCounting::Counts, AddressScope::Range},
    {FunctionCode::ReportServerId, "report server id", fixed_pdu(1), count_at(1), Broadcast::Ignore,
     Writes::No, EventCounting::Counts, AddressScope::None},
    {FunctionCode::ReadFileRecord, "read file record", count_at(1), count_at(1), Broadcast::Ignore,
     Writes::No, EventCounting::Counts, AddressScope::None},
    {FunctionCode::WriteFileRecord, "write file record", count_at(1), count_at(1),
     Broadcast::Execute, Writes::Yes, EventCounting::Counts, AddressScope::None},
    {FunctionCode::MaskWriteRegister, "mask write register", fixed_pdu(7), fixed_pdu(7),
     Broadcast::Execute, Writes::Yes, EventCounting::Counts, AddressScope::Single},
    // A read comes back, so a broadcast cannot carry it.
    {FunctionCode::ReadWriteMultipleRegisters, "read/write multiple registers", count_at(9),
     count_at(1), Broadcast::Ignore, Writes::Yes, EventCounting::Counts, AddressScope::ReadWrite},
    {FunctionCode::ReadFifoQueue, "read FIFO queue", fixed_pdu(3), count16_at(1), Broadcast::Ignore,
     Writes::No, EventCounting::Counts, AddressScope::Single},
    {FunctionCode::EncapsulatedInterface, "encapsulated interface transport",
     shaped(PduShape::DeviceIdRequest), shaped(PduShape::DeviceIdResponse), Broadcast::Ignore,
     Writes::No, EventCounting::Counts, AddressScope::None},
    {FunctionCode::ObjectMessaging, "object messaging", count_at(1), count_at(1), Broadcast::Ignore,
     Writes::No, EventCounting::Counts, AddressScope::None},
};

namespace detail {

inline constexpr std::uint8_t kNoRow = 0xFF;
static_assert(std::size(kFunctionTable) < kNoRow);

constexpr bool is_sorted_by_code() {
    for (std::size_t i = 1; i < std::size(kFunctionTable); ++i) {
        if (kFunctionTable[i - 1].code >= kFunctionTable[i].code) return false;
    }
    return true;
}
static_assert(is_sorted_by_code(), "one row per code, in ascending order");

constexpr bool no_row_has_the_exception_bit() {
    for (const FunctionRow& row : kFunctionTable) {
        if (static_cast<std::uint8_t>(row.code) & kExceptionBit) return false;
    }
    return true;
}
static_assert(no_row_has_the_exception_bit(), "codes 0x80 and up are exception responses");

// A lookup per frame must not search: the row number of every code, kNoRow where there is none.
constexpr std::array<std::uint8_t, 256> make_row_index() {
    std::array<std::uint8_t, 256> index{};
    index.fill(kNoRow);
    for (std::size_t i = 0; i < std::size(kFunctionTable); ++i)
        index[static_cast<std::uint8_t>(kFunctionTable[i].code)] = static_cast<std::uint8_t>(i);
    return index;
}

inline constexpr std::array<std::uint8_t, 256> kRowIndex = make_row_index();

}  // namespace detail

// The row of `code`, or nullptr for a code outside the table (not a public function code).
constexpr const FunctionRow* find_function(std::uint8_t code) {
    const std::uint8_t row = detail::kRowIndex[code];
    return row == detail::kNoRow ? nullptr : &kFunctionTable[row];
}

}  // namespace mblab::protocol
