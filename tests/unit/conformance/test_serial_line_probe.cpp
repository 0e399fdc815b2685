// The serial suite's requests as they go on the line [SER 2.5]: framed for RTU or ASCII, and
// spoiled on purpose (a wrong CRC or LRC, lower-case hex) for the cases about spoiled frames.
#include <gtest/gtest.h>

#include <string>

#include "client/target.hpp"
#include "conformance/catalogue.hpp"
#include "conformance/serial_line_probe.hpp"
#include "conformance/session.hpp"
#include "support/hex.hpp"

namespace mblab::conformance {
namespace {

Session session_on(const std::string& url, std::uint8_t unit = 1) {
    auto target = client::parse_target(url);
    EXPECT_TRUE(target.ok()) << target.error();
    Dut dut;
    dut.unit = unit;
    return Session(target.value(), dut, EngineOptions{});
}

std::string text(const std::vector<std::uint8_t>& bytes) {
    return {bytes.begin(), bytes.end()};
}

const std::vector<std::uint8_t> kRead = test::hex("03 00 6B 00 03");

TEST(LineProbe, RtuFramesCarryTheCrcLowByteFirstAndSpoilItsLowByte) {
    auto session = session_on("rtu:///dev/null?baud=19200");
    LineProbe line(session, Case{});
    EXPECT_EQ(test::to_hex(line.frame(0x11, kRead)), "11 03 00 6B 00 03 76 87");
    EXPECT_EQ(test::to_hex(line.frame(0x11, kRead, Spoil::Checksum)), "11 03 00 6B 00 03 89 87");
}

TEST(LineProbe, AsciiFramesAreUpperCaseAndSpoilTheLrcOrTheCase) {
    auto session = session_on("ascii:///dev/null?baud=19200");
    LineProbe line(session, Case{});
    // The example frame of [SER 2.5.2.2]: LRC 7E.
    EXPECT_EQ(text(line.frame(0x11, kRead)), ":1103006B00037E\r\n");
    EXPECT_EQ(text(line.frame(0x11, kRead, Spoil::Checksum)), ":1103006B00037F\r\n");
    EXPECT_EQ(text(line.frame(0x11, kRead, Spoil::LowerCase)), ":1103006b00037e\r\n");
}

TEST(LineProbe, AnotherAddressIsTheNextOneUnlessDeclared) {
    auto session = session_on("rtu:///dev/null", 1);
    EXPECT_EQ(LineProbe(session, Case{}).other(), 2);
    auto last = session_on("rtu:///dev/null", 247);
    EXPECT_EQ(LineProbe(last, Case{}).other(), 246);
    Case declared;
    declared.params["other_address"] = 95;
    EXPECT_EQ(LineProbe(session, declared).other(), 95);
}

}  // namespace
}  // namespace mblab::conformance
