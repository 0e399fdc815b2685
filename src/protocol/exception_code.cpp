#include "protocol/exception_code.hpp"

namespace mblab::protocol {

std::string_view exception_name(ExceptionCode code) {
    switch (code) {
        case ExceptionCode::IllegalFunction:
            return "illegal function";
        case ExceptionCode::IllegalDataAddress:
            return "illegal data address";
        case ExceptionCode::IllegalDataValue:
            return "illegal data value";
        case ExceptionCode::ServerDeviceFailure:
            return "server device failure";
        case ExceptionCode::Acknowledge:
            return "acknowledge";
        case ExceptionCode::ServerDeviceBusy:
            return "server device busy";
        case ExceptionCode::NegativeAcknowledge:
            return "negative acknowledge";
        case ExceptionCode::MemoryParityError:
            return "memory parity error";
        case ExceptionCode::GatewayPathUnavailable:
            return "gateway path unavailable";
        case ExceptionCode::GatewayTargetFailedToRespond:
            return "gateway target failed to respond";
    }
    return "unknown exception";
}

std::string_view exception_meaning(ExceptionCode code) {
    switch (code) {
        case ExceptionCode::IllegalFunction:
            return "the device does not support this function code";
        case ExceptionCode::IllegalDataAddress:
            return "the address range is not on this device";
        case ExceptionCode::IllegalDataValue:
            return "a value or length in the request is not allowed";
        case ExceptionCode::ServerDeviceFailure:
            return "the device failed while executing the request";
        case ExceptionCode::Acknowledge:
            return "the device accepted a long-running request";
        case ExceptionCode::ServerDeviceBusy:
            return "the device is busy; retry later";
        case ExceptionCode::NegativeAcknowledge:
            return "the device cannot perform the program function";
        case ExceptionCode::MemoryParityError:
            return "the device found a parity error in its memory";
        case ExceptionCode::GatewayPathUnavailable:
            return "the gateway has no path to the unit";
        case ExceptionCode::GatewayTargetFailedToRespond:
            return "the unit behind the gateway did not answer";
    }
    return "an exception code not defined by the Modbus specification";
}

}  // namespace mblab::protocol
