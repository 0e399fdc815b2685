#include "protocol/adu.hpp"

#include "protocol/adu_writer.hpp"
#include "protocol/limits.hpp"
#include "support/name_table.hpp"

namespace mblab::protocol {

const char* framing_name(Framing framing) {
    static constexpr Named<Framing, const char*> kNames[] = {
        {Framing::Mbap, "MBAP"}, {Framing::Rtu, "RTU"}, {Framing::Ascii, "ASCII"}};
    return name_of(kNames, framing, "?");
}

std::size_t write_adu(const AduHeader& header, std::span<const std::uint8_t> pdu,
                      std::span<std::uint8_t> out, std::uint8_t ascii_end) {
    switch (header.framing) {
        case Framing::Mbap:
            return write_mbap_adu({header.transaction_id, header.protocol_id, 0, header.unit}, pdu,
                                  out);
        case Framing::Rtu:
            return write_rtu_adu(header.unit, pdu, out);
        case Framing::Ascii:
            return write_ascii_adu(header.unit, pdu, out, ascii_end);
    }
    return 0;
}

std::size_t adu_size(Framing framing, std::size_t pdu_size) {
    switch (framing) {
        case Framing::Mbap:
            return limits::kMbapHeader + pdu_size;
        case Framing::Rtu:
            return pdu_size + 3;  // address, CRC
        case Framing::Ascii:
            return 2 * (pdu_size + 2) + 3;  // ':', hex of address, PDU and LRC, CR, LF
    }
    return 0;
}

}  // namespace mblab::protocol
