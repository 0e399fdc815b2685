// Telling a TLS server from a Modbus one by its first bytes, and the hello that makes a TLS
// server speak.
#include <gtest/gtest.h>

#include "client/tls_sniff.hpp"
#include "support/hex.hpp"

namespace mblab::client {
namespace {

using test::hex;

TEST(TlsSniff, RecognisesATlsAlertOrHandshakeRecord) {
    EXPECT_TRUE(looks_like_tls(hex("15 03 03 00 02 02 46")));  // protocol_version alert
    EXPECT_TRUE(looks_like_tls(hex("15 03 00 00 02 02 0A")));  // OpenSSL's answer to MBAP bytes
    EXPECT_TRUE(looks_like_tls(hex("16 03 03 00 54 02")));     // a ServerHello
    EXPECT_FALSE(looks_like_tls(hex("00 01 00 00 00 05 01 03 02 00 00")));
    EXPECT_FALSE(looks_like_tls(hex("15 03 00 00 00 06 01")));  // transaction 1503: protocol 0
    EXPECT_FALSE(looks_like_tls(hex("16 03 03 00")));
    EXPECT_FALSE(looks_like_tls(hex("15 03 03 00 03 02 46 00")));  // an alert is 2 bytes
    EXPECT_FALSE(looks_like_tls(hex("17 03 03 00 10")));  // application data is no first answer
}

TEST(TlsSniff, TheTextIsOneLineThatSaysWhatToUse) {
    const Endpoint endpoint{"192.0.2.7", 802};
    const auto text = tls_answer_text(endpoint, hex("15 03 03 00 02 02 46"));
    EXPECT_EQ(text,
              "the server at 192.0.2.7:802 answered with TLS bytes (15 03 03 00 02 ...): use "
              "mbaps://");
    EXPECT_TRUE(is_tls_answer_text(text));
    EXPECT_FALSE(is_tls_answer_text("connection closed by peer"));
    EXPECT_EQ(tls_answer_text({"::1", 802}, hex("16 03 03")),
              "the server at [::1]:802 answered with TLS bytes (16 03 03): use mbaps://");
}

// The hello's lengths agree with each other (RFC 5246 6.2.1, 7.4), or a TLS server would take
// it for garbage and close without the record that gives it away.
TEST(TlsSniff, TheClientHelloIsAWellFormedRecord) {
    const auto hello = tls_client_hello();
    ASSERT_GE(hello.size(), 9U);
    EXPECT_EQ(hello[0], 0x16);
    EXPECT_EQ(hello[1], 0x03);
    EXPECT_EQ(std::size_t{hello[3]} << 8 | hello[4], hello.size() - 5);
    EXPECT_EQ(hello[5], 0x01);  // client_hello
    EXPECT_EQ(std::size_t{hello[6]} << 16 | std::size_t{hello[7]} << 8 | hello[8],
              hello.size() - 9);
    // version, random, empty session id, then the cipher suites and compression methods.
    std::size_t at = 9 + 2 + 32;
    EXPECT_EQ(hello[at++], 0x00);
    const std::size_t suites = std::size_t{hello[at]} << 8 | hello[at + 1];
    EXPECT_EQ(suites % 2, 0U);
    at += 2 + suites;
    EXPECT_EQ(hello[at], 0x01);
    at += 1 + hello[at];
    const std::size_t extensions = std::size_t{hello[at]} << 8 | hello[at + 1];
    EXPECT_EQ(at + 2 + extensions, hello.size());
}

}  // namespace
}  // namespace mblab::client
