#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "protocol/result.hpp"
#include "robustness/pcap_reader.hpp"
#include "robustness/recon.hpp"

// Reconnaissance learned from a capture of normal traffic instead of probing: the device is sent
// nothing it would not have been sent anyway, and the facts are those of the requests its real
// clients make.
namespace mblab::robustness {

// The Modbus/TCP flows to `port` (the server is the side with that port), each direction
// reassembled in sequence order (retransmitted bytes dropped, a direction stops at a gap), cut
// into MBAP frames and paired by transaction id per flow. Learned: the unit most used among those
// with an FC 03 read answered with data; for that unit the function codes served (answered other
// than with exception 01) and not served (01), the lowest FC 03 address answered with data (the
// liveness check), the largest FC 03 quantity answered with data, the address ranges answered;
// whether units 0 and 255 were answered at all. `name` (the file) goes into the source and into
// the one-line error when no FC 03 read was answered with data.
protocol::Result<Recon, std::string> learn_recon(const PcapContents& capture, std::uint16_t port,
                                                 std::string_view name);

}  // namespace mblab::robustness
