#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "protocol/function_code.hpp"

// Function codes of the message types (not part of the public API).
namespace mblab::protocol::detail {

// The code of each typed message by its index in the Request and Response variants, which list
// the function codes in the same order. Types that carry a `function` member are read from it.
inline constexpr std::array<FunctionCode, 19> kFunctionByIndex = {
    FunctionCode::ReadCoils,             // read bits: from the member
    FunctionCode::ReadHoldingRegisters,  // read registers: from the member
    FunctionCode::WriteSingleCoil,
    FunctionCode::WriteSingleRegister,
    FunctionCode::ReadExceptionStatus,
    FunctionCode::Diagnostics,
    FunctionCode::GetCommEventCounter,
    FunctionCode::GetCommEventLog,
    FunctionCode::WriteMultipleCoils,
    FunctionCode::WriteMultipleRegisters,
    FunctionCode::ReportServerId,
    FunctionCode::ReadFileRecord,
    FunctionCode::WriteFileRecord,
    FunctionCode::MaskWriteRegister,
    FunctionCode::ReadWriteMultipleRegisters,
    FunctionCode::ReadFifoQueue,
    FunctionCode::EncapsulatedInterface,  // read device id (MEI 0E)
    FunctionCode::EncapsulatedInterface,  // other MEI types
    FunctionCode::ObjectMessaging,
};

template <class Message>
std::uint8_t function_byte(const Message& message, std::size_t index) {
    if constexpr (requires { message.function; }) {
        return static_cast<std::uint8_t>(message.function);
    } else {
        return static_cast<std::uint8_t>(kFunctionByIndex[index]);
    }
}

}  // namespace mblab::protocol::detail
