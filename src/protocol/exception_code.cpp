#include "protocol/exception_code.hpp"

#include "support/name_table.hpp"

namespace mblab::protocol {

namespace {

struct ExceptionWords {
    ExceptionCode value;
    std::string_view name;
    std::string_view meaning;
};

// [APP] section 7, with what each code means to someone reading a report.
constexpr ExceptionWords kExceptions[] = {
    {ExceptionCode::IllegalFunction, "illegal function",
     "the device does not support this function code"},
    {ExceptionCode::IllegalDataAddress, "illegal data address",
     "the address range is not on this device"},
    {ExceptionCode::IllegalDataValue, "illegal data value",
     "a value or length in the request is not allowed"},
    {ExceptionCode::ServerDeviceFailure, "server device failure",
     "the device failed while executing the request"},
    {ExceptionCode::Acknowledge, "acknowledge", "the device accepted a long-running request"},
    {ExceptionCode::ServerDeviceBusy, "server device busy", "the device is busy; retry later"},
    {ExceptionCode::NegativeAcknowledge, "negative acknowledge",
     "the device cannot perform the program function"},
    {ExceptionCode::MemoryParityError, "memory parity error",
     "the device found a parity error in its memory"},
    {ExceptionCode::GatewayPathUnavailable, "gateway path unavailable",
     "the gateway has no path to the unit"},
    {ExceptionCode::GatewayTargetFailedToRespond, "gateway target failed to respond",
     "the unit behind the gateway did not answer"},
};

}  // namespace

std::string_view exception_name(ExceptionCode code) {
    return word_of(kExceptions, code, &ExceptionWords::name, "unknown exception");
}

std::string_view exception_meaning(ExceptionCode code) {
    return word_of(kExceptions, code, &ExceptionWords::meaning,
                   "an exception code not defined by the Modbus specification");
}

}  // namespace mblab::protocol
