#include <gtest/gtest.h>

#include "conformance/dut.hpp"
#include "load/mix.hpp"
#include "support/hex.hpp"

namespace mblab::load {
namespace {

using test::hex;

std::vector<std::uint8_t> request_bytes(const MixEntry& entry, std::uint8_t unit) {
    conformance::Dut dut;
    dut.unit = unit;
    return conformance::render_bytes(
        conformance::resolve(mix_exchange(entry).request, conformance::DutFacts(dut)).value());
}

std::string expected_text(const MixEntry& entry, std::uint8_t unit) {
    conformance::Dut dut;
    dut.unit = unit;
    return conformance::to_text(
        conformance::resolve(mix_exchange(entry).expect, conformance::DutFacts(dut)).value());
}

MixEntry only(std::string_view text) {
    auto mix = parse_mix(text);
    EXPECT_TRUE(mix.ok()) << mix.error();
    EXPECT_EQ(mix->size(), 1U);
    return mix->front();
}

TEST(LoadMix, ParsesTheDocumentedExample) {
    auto mix = parse_mix("fc3:125=70,fc16:10=20,fc1:100=10");
    ASSERT_TRUE(mix.ok()) << mix.error();
    ASSERT_EQ(mix->size(), 3U);
    EXPECT_EQ((*mix)[0].function, 0x03);
    EXPECT_EQ((*mix)[0].quantity, 125);
    EXPECT_EQ((*mix)[0].address, 0);
    EXPECT_EQ((*mix)[0].weight, 70U);
    EXPECT_EQ((*mix)[0].text, "fc3:125");
    EXPECT_EQ((*mix)[1].function, 0x10);
    EXPECT_EQ((*mix)[1].address, 0x0010);  // writes stay off the SEMI signature
    EXPECT_EQ((*mix)[2].function, 0x01);
    EXPECT_EQ((*mix)[2].weight, 10U);
}

TEST(LoadMix, DefaultsAddressesAndHex) {
    auto entry = only("fc0x10");
    EXPECT_EQ(entry.function, 0x10);
    EXPECT_EQ(entry.quantity, 1);
    EXPECT_EQ(entry.weight, 1U);
    entry = only("fc4:2@0x100=3");
    EXPECT_EQ(entry.address, 0x100);
    EXPECT_EQ(entry.text, "fc4:2@0x100");
}

TEST(LoadMix, RefusesWhatCannotBeSent) {
    auto error = [](std::string_view text) {
        auto mix = parse_mix(text);
        return mix.ok() ? std::string("accepted") : mix.error();
    };
    EXPECT_EQ(error("fc3:126"),
              "--mix entry 'fc3:126': the quantity must be 1..125 for read holding registers "
              "(expected fcCODE[:QUANTITY][@ADDRESS][=WEIGHT], e.g. fc3:125=70)");
    EXPECT_NE(error("fc8").find("function 8 is not one the generator sends (1, 2, 3, 4, 5, 6, "
                                "15, 16)"),
              std::string::npos);
    EXPECT_NE(error("f3").find("it must start with fc"), std::string::npos);
    EXPECT_NE(error("fc3:0").find("the quantity must be 1..125"), std::string::npos);
    EXPECT_NE(error("fc3=0").find("the weight must be"), std::string::npos);
    EXPECT_NE(error("fc3:10@65530").find("runs past address 65535"), std::string::npos);
    EXPECT_NE(error("fc5:2").find("the quantity must be 1..1"), std::string::npos);
    EXPECT_EQ(error(""), "--mix names no requests");
}

TEST(LoadMix, RequestsAndAnswersOnTheWire) {
    EXPECT_EQ(request_bytes(only("fc3:125"), 1), hex("00 00 00 00 00 06 01 03 00 00 00 7D"));
    EXPECT_EQ(expected_text(only("fc3:2"), 1), "00 00 00 00 {len} 01 03 04 XX XX XX XX");
    EXPECT_EQ(request_bytes(only("fc1:10@5"), 0), hex("00 00 00 00 00 06 00 01 00 05 00 0A"));
    EXPECT_EQ(expected_text(only("fc1:10"), 0), "00 00 00 00 {len} 00 01 02 XX XX");
    EXPECT_EQ(request_bytes(only("fc5"), 7), hex("00 00 00 00 00 06 07 05 00 10 FF 00"));
    EXPECT_EQ(expected_text(only("fc5"), 7), "00 00 00 00 {len} 07 05 00 10 FF 00");
    EXPECT_EQ(request_bytes(only("fc6@0x20"), 1), hex("00 00 00 00 00 06 01 06 00 20 12 34"));
    EXPECT_EQ(request_bytes(only("fc15:10"), 1),
              hex("00 00 00 00 00 09 01 0F 00 10 00 0A 02 55 01"));
    EXPECT_EQ(expected_text(only("fc15:10"), 1), "00 00 00 00 {len} 01 0F 00 10 00 0A");
    EXPECT_EQ(request_bytes(only("fc16:2"), 1),
              hex("00 00 00 00 00 0B 01 10 00 10 00 02 04 12 34 12 34"));
    EXPECT_EQ(expected_text(only("fc16:2"), 1), "00 00 00 00 {len} 01 10 00 10 00 02");
}

}  // namespace
}  // namespace mblab::load
