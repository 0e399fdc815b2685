#include "server/bare_pdu.hpp"

#include "protocol/function_table.hpp"
#include "protocol/mbap_header.hpp"
#include "protocol/request.hpp"

namespace mblab::server {

namespace {

// A header whose length field accounts for exactly the bytes that came: MBAP, whatever else
// those bytes could also be read as.
bool is_whole_mbap(std::span<const std::uint8_t> bytes) {
    const auto frame = protocol::read_mbap_frame(bytes);
    return frame && !frame->pdu.empty() &&
           frame->header.protocol_id == protocol::kModbusProtocolId &&
           frame->header.length <= frame->pdu.size() + 1;
}

}  // namespace

bool is_bare_pdu(std::span<const std::uint8_t> first_bytes) {
    if (first_bytes.empty() || is_whole_mbap(first_bytes)) return false;
    // Only a public code's request can be told from the start of a header: any byte may open a
    // transaction id, and the decoder takes any other code's bytes as they are.
    return protocol::find_function(first_bytes.front()) != nullptr &&
           protocol::decode_request(first_bytes).ok();
}

}  // namespace mblab::server
