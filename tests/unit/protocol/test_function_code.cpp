#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "protocol/exception_code.hpp"
#include "protocol/function_code.hpp"

namespace mblab::protocol {
namespace {

TEST(FunctionCode, PublicCodesAreTheOnesMblabDecodes) {
    const std::uint8_t expected[] = {0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x07, 0x08, 0x0B, 0x0C,
                                     0x0F, 0x10, 0x11, 0x14, 0x15, 0x16, 0x17, 0x18, 0x2B, 0x5B};
    std::string listed;
    for (int code = 0; code <= 0xFF; ++code) {
        if (is_public_function(static_cast<std::uint8_t>(code))) listed += char(code);
    }
    EXPECT_EQ(listed, std::string(std::begin(expected), std::end(expected)));
}

// Known codes by their [APP] name, any other by its number.
TEST(FunctionCode, Names) {
    const std::pair<std::uint8_t, std::string_view> names[] = {
        {0x03, "read holding registers"},
        {0x17, "read/write multiple registers"},
        {0x2B, "encapsulated interface transport"},
        {0x5B, "object messaging"},
        {0x00, "function 0x00"},
        {0x25, "function 0x25"},
        {0x41, "function 0x41"},
        {0xAB, "function 0xAB"},
        {0xFF, "function 0xFF"},
    };
    for (const auto& [code, name] : names)
        EXPECT_EQ(function_name(code), name) << "code " << int{code};
}

TEST(DiagnosticSub, KnownSubFunctionsAreThoseOfApp681) {
    std::string listed;
    for (int sub = 0; sub <= 0xFFFF; ++sub) {
        if (is_known_diagnostic_sub(static_cast<std::uint16_t>(sub))) listed += char(sub);
    }
    EXPECT_EQ(listed,
              std::string("\x00\x01\x02\x03\x04\x0A\x0B\x0C\x0D\x0E\x0F\x10\x11\x12\x14", 15));
}

TEST(DiagnosticSub, Names) {
    const std::pair<std::uint16_t, std::string_view> names[] = {
        {0x00, "return query data"},
        {0x04, "force listen only mode"},
        {0x14, "clear overrun counter and flag"},
        {0x13, "reserved sub-function"},
        {0xFFFF, "reserved sub-function"},
    };
    for (const auto& [sub, name] : names)
        EXPECT_EQ(diagnostic_sub_name(sub), name) << "sub-function " << sub;
}

// [APP] 7 defines 01-08, 0A and 0B; every other byte is named as unknown, never as a neighbour.
TEST(ExceptionCode, EveryDefinedCodeHasItsOwnNameAndMeaning) {
    const std::uint8_t defined[] = {0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x07, 0x08, 0x0A, 0x0B};
    std::string named;
    std::vector<std::string_view> names;
    for (int byte = 0; byte <= 0xFF; ++byte) {
        const auto code = static_cast<ExceptionCode>(byte);
        if (exception_name(code) == "unknown exception") {
            EXPECT_EQ(exception_meaning(code),
                      "an exception code not defined by the Modbus specification");
            continue;
        }
        named += char(byte);
        names.push_back(exception_name(code));
        EXPECT_NE(exception_meaning(code).find("the "), std::string_view::npos) << byte;
    }
    EXPECT_EQ(named, std::string(std::begin(defined), std::end(defined)));
    EXPECT_EQ(exception_name(ExceptionCode::GatewayTargetFailedToRespond),
              "gateway target failed to respond");
    std::sort(names.begin(), names.end());
    EXPECT_EQ(std::adjacent_find(names.begin(), names.end()), names.end());
}

}  // namespace
}  // namespace mblab::protocol
