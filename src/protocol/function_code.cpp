#include "protocol/function_code.hpp"

#include <array>

#include "protocol/function_table.hpp"

namespace mblab::protocol {

namespace {

// "function 0xNN" for every code, built at compile time so naming an unknown code never
// allocates and the returned view stays valid for the life of the program.
struct UnknownFunctionNames {
    static constexpr std::size_t kLength = 13;  // "function 0x41"
    std::array<std::array<char, kLength>, 256> names{};

    constexpr UnknownFunctionNames() {
        constexpr char kDigits[] = "0123456789ABCDEF";
        constexpr char kPrefix[] = "function 0x";
        for (std::size_t code = 0; code < names.size(); ++code) {
            for (std::size_t i = 0; i + 1 < sizeof kPrefix; ++i)
                names[code][i] = kPrefix[i];
            names[code][kLength - 2] = kDigits[code >> 4];
            names[code][kLength - 1] = kDigits[code & 0xF];
        }
    }
};

constexpr UnknownFunctionNames kUnknownFunctionNames;

}  // namespace

bool is_public_function(std::uint8_t code) {
    return find_function(code) != nullptr;
}

std::string_view function_name(std::uint8_t code) {
    if (const FunctionRow* row = find_function(code)) return row->name;
    const auto& name = kUnknownFunctionNames.names[code];
    return {name.data(), name.size()};
}

bool is_known_diagnostic_sub(std::uint16_t sub) {
    switch (static_cast<DiagnosticSub>(sub)) {
        case DiagnosticSub::ReturnQueryData:
        case DiagnosticSub::RestartCommunications:
        case DiagnosticSub::ReturnDiagnosticRegister:
        case DiagnosticSub::ChangeAsciiDelimiter:
        case DiagnosticSub::ForceListenOnly:
        case DiagnosticSub::ClearCounters:
        case DiagnosticSub::BusMessageCount:
        case DiagnosticSub::BusCommunicationErrorCount:
        case DiagnosticSub::BusExceptionErrorCount:
        case DiagnosticSub::ServerMessageCount:
        case DiagnosticSub::ServerNoResponseCount:
        case DiagnosticSub::ServerNakCount:
        case DiagnosticSub::ServerBusyCount:
        case DiagnosticSub::BusCharacterOverrunCount:
        case DiagnosticSub::ClearOverrunCounter:
            return true;
    }
    return false;
}

std::string_view diagnostic_sub_name(std::uint16_t sub) {
    switch (static_cast<DiagnosticSub>(sub)) {
        case DiagnosticSub::ReturnQueryData:
            return "return query data";
        case DiagnosticSub::RestartCommunications:
            return "restart communications option";
        case DiagnosticSub::ReturnDiagnosticRegister:
            return "return diagnostic register";
        case DiagnosticSub::ChangeAsciiDelimiter:
            return "change ASCII input delimiter";
        case DiagnosticSub::ForceListenOnly:
            return "force listen only mode";
        case DiagnosticSub::ClearCounters:
            return "clear counters and diagnostic register";
        case DiagnosticSub::BusMessageCount:
            return "return bus message count";
        case DiagnosticSub::BusCommunicationErrorCount:
            return "return bus communication error count";
        case DiagnosticSub::BusExceptionErrorCount:
            return "return bus exception error count";
        case DiagnosticSub::ServerMessageCount:
            return "return server message count";
        case DiagnosticSub::ServerNoResponseCount:
            return "return server no response count";
        case DiagnosticSub::ServerNakCount:
            return "return server NAK count";
        case DiagnosticSub::ServerBusyCount:
            return "return server busy count";
        case DiagnosticSub::BusCharacterOverrunCount:
            return "return bus character overrun count";
        case DiagnosticSub::ClearOverrunCounter:
            return "clear overrun counter and flag";
    }
    return "reserved sub-function";
}

}  // namespace mblab::protocol
