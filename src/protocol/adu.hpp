#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

// The application data unit with its framing taken off: the same header for Modbus/TCP, RTU and
// ASCII, so nothing above the framer needs to know which one carried a PDU.
namespace mblab::protocol {

enum class Framing : std::uint8_t {
    Mbap,   // Modbus/TCP: MBAP header, transaction ids
    Rtu,    // address, PDU, CRC-16
    Ascii,  // ':' hex(address, PDU, LRC) CR LF
};

// "MBAP", "RTU", "ASCII".
const char* framing_name(Framing framing);

// The MBAP protocol identifier of Modbus [TCPG 3.1.3]: a frame with any other is not Modbus.
inline constexpr std::uint16_t kModbusProtocolId = 0;

struct AduHeader {
    Framing framing = Framing::Mbap;
    std::uint8_t unit = 0;  // unit id (MBAP) or serial address (RTU, ASCII)
    // MBAP only; 0 on a serial line, which pairs answers by order alone.
    std::uint16_t transaction_id = 0;
    // MBAP only. A lenient framer lets other values than Modbus's through for the tester to judge.
    std::uint16_t protocol_id = kModbusProtocolId;
    // MBAP only: the length field as received (unit id and PDU bytes), so that a reader can judge
    // a frame's header fields without going back to its bytes. write_adu() computes its own.
    std::uint16_t length = 0;

    bool has_transaction() const { return framing == Framing::Mbap; }
    friend bool operator==(const AduHeader&, const AduHeader&) = default;
};

// A whole ADU as a header and a view of its PDU (function code first).
struct Adu {
    AduHeader header;
    std::span<const std::uint8_t> pdu;
};

// Writes `pdu` under `header` in its framing into `out` (the MBAP length field is computed; ASCII
// ends with CR and `ascii_end`). Returns the bytes written, 0 when `out` is too small. The PDU
// limit of 253 bytes is not enforced: the tester must be able to put oversized frames on the
// wire. For MBAP and RTU, `pdu` may already sit where it belongs in `out` (a server writes its
// answer in place).
std::size_t write_adu(const AduHeader& header, std::span<const std::uint8_t> pdu,
                      std::span<std::uint8_t> out, std::uint8_t ascii_end = '\n');

// Bytes a PDU of `pdu_size` takes in `framing`.
std::size_t adu_size(Framing framing, std::size_t pdu_size);

}  // namespace mblab::protocol
