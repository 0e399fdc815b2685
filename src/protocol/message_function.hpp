#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <utility>
#include <variant>

#include "protocol/function_code.hpp"
#include "protocol/function_table.hpp"
#include "protocol/request.hpp"
#include "protocol/response.hpp"

// Function codes of the message types (not part of the public API).
namespace mblab::protocol::detail {

// The request and response types of one function code whose messages do not carry the code.
template <FunctionCode Code, class RequestMessage, class ResponseMessage>
struct MessagePair {
    static constexpr FunctionCode code = Code;
    template <class Message>
    static constexpr bool holds =
        std::is_same_v<Message, RequestMessage> || std::is_same_v<Message, ResponseMessage>;
};

template <class... Pairs>
struct CodeByType {
    template <class Message>
    static constexpr FunctionCode of() {
        static_assert((static_cast<int>(Pairs::template holds<Message>) + ...) == 1,
                      "a message type without a `function` member needs one pair in CodeByMessage");
        FunctionCode code{};
        static_cast<void>(((Pairs::template holds<Message> && (code = Pairs::code, true)) || ...));
        return code;
    }
    static constexpr bool all_have_rows =
        ((find_function(static_cast<std::uint8_t>(Pairs::code)) != nullptr) && ...);
};

// Looked up by type, so the order of the Request and Response variants does not matter. Types
// with a `function` member (read bits, read registers, raw) are not listed: they carry their code.
using CodeByMessage = CodeByType<
    MessagePair<FunctionCode::WriteSingleCoil, WriteSingleCoilRequest, WriteSingleCoilResponse>,
    MessagePair<FunctionCode::WriteSingleRegister, WriteSingleRegisterRequest,
                WriteSingleRegisterResponse>,
    MessagePair<FunctionCode::ReadExceptionStatus, ReadExceptionStatusRequest,
                ReadExceptionStatusResponse>,
    MessagePair<FunctionCode::Diagnostics, DiagnosticsRequest, DiagnosticsResponse>,
    MessagePair<FunctionCode::GetCommEventCounter, GetCommEventCounterRequest,
                GetCommEventCounterResponse>,
    MessagePair<FunctionCode::GetCommEventLog, GetCommEventLogRequest, GetCommEventLogResponse>,
    MessagePair<FunctionCode::WriteMultipleCoils, WriteMultipleCoilsRequest,
                WriteMultipleCoilsResponse>,
    MessagePair<FunctionCode::WriteMultipleRegisters, WriteMultipleRegistersRequest,
                WriteMultipleRegistersResponse>,
    MessagePair<FunctionCode::ReportServerId, ReportServerIdRequest, ReportServerIdResponse>,
    MessagePair<FunctionCode::ReadFileRecord, ReadFileRecordRequest, ReadFileRecordResponse>,
    MessagePair<FunctionCode::WriteFileRecord, WriteFileRecordRequest, WriteFileRecordResponse>,
    MessagePair<FunctionCode::MaskWriteRegister, MaskWriteRegisterRequest,
                MaskWriteRegisterResponse>,
    MessagePair<FunctionCode::ReadWriteMultipleRegisters, ReadWriteMultipleRegistersRequest,
                ReadWriteMultipleRegistersResponse>,
    MessagePair<FunctionCode::ReadFifoQueue, ReadFifoQueueRequest, ReadFifoQueueResponse>,
    MessagePair<FunctionCode::EncapsulatedInterface, ReadDeviceIdRequest, ReadDeviceIdResponse>,
    MessagePair<FunctionCode::EncapsulatedInterface, EncapsulatedRequest, EncapsulatedResponse>,
    MessagePair<FunctionCode::ObjectMessaging, ObjectMessagingRequest, ObjectMessagingResponse>>;

static_assert(CodeByMessage::all_have_rows, "every code of a message type needs a row");

template <class Message>
constexpr std::uint8_t function_byte(const Message& message) {
    if constexpr (requires { message.function; }) {
        return static_cast<std::uint8_t>(message.function);
    } else {
        return static_cast<std::uint8_t>(CodeByMessage::of<Message>());
    }
}

}  // namespace mblab::protocol::detail
