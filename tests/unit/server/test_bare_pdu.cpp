// The first plaintext of a TLS session: MBAP, or the bare PDU of an early draft of [SEC].
#include <gtest/gtest.h>

#include "server/bare_pdu.hpp"
#include "support/hex.hpp"

namespace mblab::test {
namespace {

bool bare(std::string_view bytes) {
    return server::is_bare_pdu(hex(bytes));
}

TEST(BarePdu, WholeRequestsWithoutHeaderAreBare) {
    EXPECT_TRUE(bare("03 00 00 00 02"));           // pymodbus's TLS framer, FC 03
    EXPECT_TRUE(bare("10 00 00 00 01 02 12 34"));  // FC 16: its length field would be 0x0102
    EXPECT_TRUE(bare("08 00 00 12 34"));
}

TEST(BarePdu, MbapIsNotBare) {
    EXPECT_FALSE(bare("00 01 00 00 00 06 01 03 00 00 00 02"));
    // Two pipelined frames in one record.
    EXPECT_FALSE(bare("03 01 00 00 00 06 01 03 00 00 00 01 03 02 00 00 00 06 01 03 00 00 00 01"));
    // The first bytes of a header split across records.
    EXPECT_FALSE(bare("00 01 00 00 00 06 01"));
    EXPECT_FALSE(bare("01 03 00 00 00 06 01"));  // transaction 0x0103
    EXPECT_FALSE(bare("00 01"));
    EXPECT_FALSE(bare(""));
}

}  // namespace
}  // namespace mblab::test
