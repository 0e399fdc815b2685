// What issue #14's "A CLI that guides" promises, checked as a user sees it: exit status and the
// exact lines printed.
#include <gtest/gtest.h>

#include "test_client_support.hpp"

namespace mblab::test {
namespace {

class CliGuides : public ClientCliTest {
  protected:
    void SetUp() override { start_reference_server(); }
};

// One hex digit is one byte, so `03 0 0 0 1` is the five bytes it reads as.
TEST_F(CliGuides, RawTakesASingleDigitAsOneByte) {
    auto ran = mblab("raw", {"03", "0", "0", "0", "1"});
    EXPECT_EQ(ran.status, 0) << ran.err;
    EXPECT_EQ(ran.out.substr(0, ran.out.find('\n')), "request  03 00 00 00 01");
    auto runs = mblab("raw", {"030000", "0x00:01"});
    EXPECT_EQ(runs.status, 0) << runs.err;
    EXPECT_EQ(runs.out.substr(0, runs.out.find('\n')), "request  03 00 00 00 01");
}

// An odd run of digits is neither a byte nor whole bytes: refused before anything is sent.
TEST_F(CliGuides, RawRefusesAnOddRunOfDigits) {
    auto ran = mblab("raw", {"03", "0", "123", "1"});
    EXPECT_EQ(ran.status, 2);
    EXPECT_EQ(ran.out, "");
    EXPECT_EQ(ran.err,
              "mblab raw: PDU token 3 '123' has an odd number of hex digits: give each byte as 1 "
              "or 2 digits, or whole bytes run together (03 00 00 00 0A or 030000000A)\n");
    auto not_hex = mblab("raw", {"03", "zz"});
    EXPECT_EQ(not_hex.status, 2);
    EXPECT_EQ(not_hex.err,
              "mblab raw: 'zz' is not hex: give the PDU as hex bytes, e.g. 03 00 00 00 "
              "0A\n");
}

}  // namespace
}  // namespace mblab::test
