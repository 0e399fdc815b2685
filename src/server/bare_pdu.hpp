#pragma once

#include <cstdint>
#include <span>

namespace mblab::server {

// Whether the first plaintext of a Modbus/TCP Security session is a bare PDU: a whole request
// without the MBAP header, as an early draft of [SEC] framed it (pymodbus 3.0's TLS framer still
// does). The spec carries MBAP unchanged inside TLS; framed as MBAP such bytes would be cut at
// the wrong places, so the server refuses the client with this reason instead.
bool is_bare_pdu(std::span<const std::uint8_t> first_bytes);

}  // namespace mblab::server
