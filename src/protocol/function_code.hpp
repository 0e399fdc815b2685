#pragma once

#include <cstdint>
#include <string_view>

namespace mblab::protocol {

// Public function codes of [APP] plus 0x5B (SEMI object messaging, CTP 7.13). Each has a
// row in kFunctionTable (function_table.hpp) that holds what mblab knows about it.
enum class FunctionCode : std::uint8_t {
    ReadCoils = 0x01,
    ReadDiscreteInputs = 0x02,
    ReadHoldingRegisters = 0x03,
    ReadInputRegisters = 0x04,
    WriteSingleCoil = 0x05,
    WriteSingleRegister = 0x06,
    ReadExceptionStatus = 0x07,
    Diagnostics = 0x08,
    GetCommEventCounter = 0x0B,
    GetCommEventLog = 0x0C,
    WriteMultipleCoils = 0x0F,
    WriteMultipleRegisters = 0x10,
    ReportServerId = 0x11,
    ReadFileRecord = 0x14,
    WriteFileRecord = 0x15,
    MaskWriteRegister = 0x16,
    ReadWriteMultipleRegisters = 0x17,
    ReadFifoQueue = 0x18,
    EncapsulatedInterface = 0x2B,
    ObjectMessaging = 0x5B,
};

inline constexpr std::uint8_t kExceptionBit = 0x80;
inline constexpr std::uint8_t kMeiReadDeviceId = 0x0E;
inline constexpr std::uint8_t kMeiCanopen = 0x0D;

// True for the codes with a row in kFunctionTable (the ones mblab decodes into typed messages).
bool is_public_function(std::uint8_t code);
// "read holding registers", or "function 0x41" for others.
std::string_view function_name(std::uint8_t code);

// FC 08 sub-functions of [APP] 6.8.1, one row each: the enumerator, the sub-function code, its
// name, and whether the answer's data field repeats the request's (the others answer with a
// register or a counter).
#define MBLAB_DIAGNOSTIC_SUBS(X)                                                       \
    X(ReturnQueryData, 0x00, "return query data", true)                                \
    X(RestartCommunications, 0x01, "restart communications option", true)              \
    X(ReturnDiagnosticRegister, 0x02, "return diagnostic register", false)             \
    X(ChangeAsciiDelimiter, 0x03, "change ASCII input delimiter", true)                \
    X(ForceListenOnly, 0x04, "force listen only mode", true)                           \
    X(ClearCounters, 0x0A, "clear counters and diagnostic register", true)             \
    X(BusMessageCount, 0x0B, "return bus message count", false)                        \
    X(BusCommunicationErrorCount, 0x0C, "return bus communication error count", false) \
    X(BusExceptionErrorCount, 0x0D, "return bus exception error count", false)         \
    X(ServerMessageCount, 0x0E, "return server message count", false)                  \
    X(ServerNoResponseCount, 0x0F, "return server no response count", false)           \
    X(ServerNakCount, 0x10, "return server NAK count", false)                          \
    X(ServerBusyCount, 0x11, "return server busy count", false)                        \
    X(BusCharacterOverrunCount, 0x12, "return bus character overrun count", false)     \
    X(ClearOverrunCounter, 0x14, "clear overrun counter and flag", true)

enum class DiagnosticSub : std::uint16_t {
#define MBLAB_DIAGNOSTIC_ENUMERATOR(enumerator, code, name, echoes) enumerator = code,
    MBLAB_DIAGNOSTIC_SUBS(MBLAB_DIAGNOSTIC_ENUMERATOR)
#undef MBLAB_DIAGNOSTIC_ENUMERATOR
};

bool is_known_diagnostic_sub(std::uint16_t sub);
std::string_view diagnostic_sub_name(std::uint16_t sub);
// Whether the answer to `sub` repeats the request's data field; the others return a register or
// a counter. False for a sub-function [APP] does not define.
bool diagnostic_answer_echoes(std::uint16_t sub);

}  // namespace mblab::protocol
