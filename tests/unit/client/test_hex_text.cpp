#include <gtest/gtest.h>

#include <string>
#include <utility>

#include "client/hex_text.hpp"
#include "support/hex.hpp"

namespace mblab::client {
namespace {

using test::hex;

TEST(HexText, BytesAreUppercaseWithOneSpaceBetween) {
    EXPECT_EQ(hex_bytes(hex("0a ff 00")), "0A FF 00");
    EXPECT_EQ(hex_bytes(hex("7e")), "7E");
    EXPECT_EQ(hex_bytes({}), "");
}

TEST(HexText, FieldValuesCarryTheirWidthAndDropWhatIsWider) {
    const std::pair<std::string, std::string> shown[] = {{hex16(0x2A), "0x002A"},
                                                         {hex16(0x1ABCD), "0xABCD"},
                                                         {hex8(0x2A), "0x2A"},
                                                         {hex8(0x1FF), "0xFF"}};
    for (const auto& [got, want] : shown)
        EXPECT_EQ(got, want);
}

}  // namespace
}  // namespace mblab::client
