#pragma once

#include <cstdint>
#include <span>

#include "protocol/function_code.hpp"

// Field layouts that a request and its response share: the response echoes the request, or
// carries the same fields back. Each message type derives from its layout instead of naming it
// with `using`, so that it stays a type of its own (an alternative of its variant, with its own
// name). A layout names its function code as `kFunction`, a template argument where the layout
// serves several codes; the raw layout, which carries any code, holds it as `function`.
namespace mblab::protocol {

// 07, 0B, 0C, 11 requests: the function code is the whole PDU.
template <FunctionCode Code>
struct CodeOnly {
    static constexpr FunctionCode kFunction = Code;
};

// 05, 06, both ways: one address and the value written there.
template <FunctionCode Code>
struct AddressValue {
    static constexpr FunctionCode kFunction = Code;
    std::uint16_t address = 0;
    std::uint16_t value = 0;
};

// 0F, 10 responses: the echo of the request's starting address and quantity.
template <FunctionCode Code>
struct AddressQuantity {
    static constexpr FunctionCode kFunction = Code;
    std::uint16_t address = 0;
    std::uint16_t quantity = 0;
};

// 08, both ways.
struct DiagnosticsFields {
    static constexpr FunctionCode kFunction = FunctionCode::Diagnostics;
    std::uint16_t sub_function = 0;
    std::span<const std::uint8_t> data;
};

// 15, both ways: sub-requests of 7 + 2 x length bytes, already validated.
struct WriteFileRecordFields {
    static constexpr FunctionCode kFunction = FunctionCode::WriteFileRecord;
    std::span<const std::uint8_t> sub_requests;
};

// 16, both ways.
struct MaskWriteFields {
    static constexpr FunctionCode kFunction = FunctionCode::MaskWriteRegister;
    std::uint16_t address = 0;
    std::uint16_t and_mask = 0;
    std::uint16_t or_mask = 0;
};

// 2B with MEI 0D (CANopen), both ways, carried as opaque bytes.
struct CanopenFields {
    static constexpr FunctionCode kFunction = FunctionCode::EncapsulatedInterface;
    std::uint8_t mei_type = kMeiCanopen;
    std::span<const std::uint8_t> data;
};

// The typed messages, one name for each request and response pair (FooRequest in request.hpp,
// FooResponse in response.hpp): the alternatives of both variants, in their order, so a new
// pair is listed once.
// clang-format off
#define MBLAB_MESSAGE_KINDS(X)    \
    X(ReadBits)                   \
    X(ReadRegisters)              \
    X(WriteSingleCoil)            \
    X(WriteSingleRegister)        \
    X(ReadExceptionStatus)        \
    X(Diagnostics)                \
    X(GetCommEventCounter)        \
    X(GetCommEventLog)            \
    X(WriteMultipleCoils)         \
    X(WriteMultipleRegisters)     \
    X(ReportServerId)             \
    X(ReadFileRecord)             \
    X(WriteFileRecord)            \
    X(MaskWriteRegister)          \
    X(ReadWriteMultipleRegisters) \
    X(ReadFifoQueue)              \
    X(ReadDeviceId)               \
    X(Encapsulated)               \
    X(ObjectMessaging)
// clang-format on

// Any other function code, both ways, carried as bytes.
struct RawFields {
    std::uint8_t function = 0;
    std::span<const std::uint8_t> data;
};

}  // namespace mblab::protocol
