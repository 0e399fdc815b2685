#include "server/bare_pdu.hpp"

#include "protocol/function_table.hpp"
#include "protocol/limits.hpp"
#include "protocol/request.hpp"

namespace mblab::server {

namespace {

// A header whose length field accounts for exactly the bytes that came: MBAP, whatever else
// those bytes could also be read as.
bool is_whole_mbap(std::span<const std::uint8_t> bytes) {
    if (bytes.size() < protocol::limits::kMbapHeader + 1) return false;
    const unsigned protocol_id = bytes[2] << 8 | bytes[3];
    const std::size_t length = static_cast<std::size_t>(bytes[4] << 8 | bytes[5]);
    return protocol_id == 0 && length + 6 <= bytes.size();
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
