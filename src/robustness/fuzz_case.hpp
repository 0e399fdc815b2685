#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

// What the robustness tester sends: cases made of steps, each step bytes on one of the case's
// connections. A step is the unit that minimisation removes and that a reproducer line holds.
namespace mblab::robustness {

// The bad-input classes (docs/robustness.md, "What is tried") that a tester can try
// over Modbus/TCP or a serial line, plus the seeded mutation that follows them.
enum class BadInput : std::uint8_t {
    ProtocolId,       // 1: protocol id other than 0
    MbapLength,       // 2: MBAP length shorter or longer than the bytes, 0, 1, over 254
    Oversize,         // 3: PDU over 253 bytes, ADU over 260
    Truncated,        // 4: a request cut short, a bare function code
    Quantity,         // 5: quantity 0, over the limit, all ones
    ByteCount,        // 6: byte count that disagrees with the quantity
    AddressWrap,      // 7: address + quantity past 0xFFFF, write ranges outside the map
    UnknownFunction,  // 8: every code that is not a public one, user-defined ones included
    SubFunction,      // FC 08 sub-functions, FC 2B MEI types, read codes and object ids
    FileRecord,       // 9: file record sub-requests that overrun the frame
    UnitId,           // 11: every unit id
    SplitFrame,       // 10: one request over several segments, with pauses
    PartialHeader,    // 14: part of an MBAP header, then silence on an open connection
    Pipelined,        // 10: many requests in one segment
    ManyConnections,  // 12: many connections at once, a thousand held open through the check
    SlowReader,       // 14: requests sent, answers never read, the connection held open
    HalfOpen,         // 14: a partial request, then the client gone without a FIN
    Flood,            // 10: requests streamed without waiting, writes among them checked
    Boundary,         // 0, 1, max, max+1, all ones in addresses, quantities, transaction ids
    FrameCheck,       // serial: a bad CRC (RTU) or LRC (ASCII)
    ShortFrame,       // serial: frames shorter than address + function + check
    LineGap,          // serial: a silence longer than t1.5 inside an RTU frame
    Noise,            // serial: stray bytes between frames
    AsciiText,        // serial: odd hex length, characters that are not hex, no CR LF
    Pairwise,         // every pair of boundary values of two request fields, MBAP ones included
    Mutation,         // seeded random changes to valid requests
};

inline constexpr std::size_t kBadInputCount = static_cast<std::size_t>(BadInput::Mutation) + 1;

// "protocol-id", "mbap-length", ...: the class as reports and --class name it.
std::string_view class_name(BadInput kind);
// What a robust device does with the class's input, for reports.
std::string_view class_expectation(BadInput kind);
std::optional<BadInput> class_named(std::string_view name);

struct Step {
    Step() = default;
    Step(std::size_t on, std::vector<std::uint8_t> data,
         std::chrono::milliseconds silence = std::chrono::milliseconds(0))
        : connection(on), bytes(std::move(data)), pause(silence) {}

    std::size_t connection = 0;  // which of the case's connections carries it
    std::vector<std::uint8_t> bytes;
    std::chrono::milliseconds pause{0};  // silence after it, before the next step
    // The connection's answers are never read: the device's send buffer fills (a slow reader).
    bool unread = false;
    // After the bytes, the connection is let go without a FIN (a half-open connection).
    bool vanish = false;
};

// A flood's writes: FC 06 of 1, 2, 3, ... to one holding register, answers read as they come.
// Once the device is judged alive, the register must hold a value no older than the last write
// it acknowledged: an acknowledged write that is lost is a finding.
struct WriteLedger {
    std::uint16_t address = 0;
};

struct FuzzCase {
    FuzzCase() = default;
    FuzzCase(BadInput what, std::string called, std::vector<Step> sent = {}, bool hold = false)
        : kind(what), name(std::move(called)), steps(std::move(sent)), hold_open(hold) {}

    BadInput kind = BadInput::Mutation;
    std::string name;  // "protocol id 0x0001", "FC 0x10 byte count 3 for 1 register"
    std::vector<Step> steps;
    // The case's connections stay open through the liveness check that follows it (a partial
    // header left hanging must not stall the others).
    bool hold_open = false;
    std::optional<WriteLedger> ledger;
};

// An MBAP frame: header fields as given, then `pdu`. `length` is the MBAP length field; nullopt
// is the right one (unit id + PDU).
std::vector<std::uint8_t> mbap_frame(std::uint16_t transaction, std::uint8_t unit,
                                     std::span<const std::uint8_t> pdu, std::uint16_t protocol = 0,
                                     std::optional<std::uint16_t> length = std::nullopt);

}  // namespace mblab::robustness
