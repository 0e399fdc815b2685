#pragma once

#include <cstdint>
#include <string_view>

namespace mblab::protocol {

// Exception codes of [APP] section 7.
enum class ExceptionCode : std::uint8_t {
    IllegalFunction = 0x01,
    IllegalDataAddress = 0x02,
    IllegalDataValue = 0x03,
    ServerDeviceFailure = 0x04,
    Acknowledge = 0x05,
    ServerDeviceBusy = 0x06,
    NegativeAcknowledge = 0x07,
    MemoryParityError = 0x08,
    GatewayPathUnavailable = 0x0A,
    GatewayTargetFailedToRespond = 0x0B,
};

// "illegal data address" and similar: the name users see in reports.
std::string_view exception_name(ExceptionCode code);
// One sentence saying what the code means to a user.
std::string_view exception_meaning(ExceptionCode code);

}  // namespace mblab::protocol
