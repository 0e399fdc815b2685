#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "conformance/client_examiner.hpp"
#include "support/hex.hpp"

// The examiner of `mblab conform-client` on a serial line (RTU and ASCII), hex in and hex out on
// a manual clock: the line is connection 0, answers carry the slave address and a CRC or LRC.
namespace mblab::conformance {
namespace {

using namespace std::chrono_literals;
using test::hex;
using test::to_hex;
using Clock = ClientExaminer::Clock;

// Read holding registers 100 and 101 of slave 1.
const std::string kRequest = "01 03 00 64 00 02 85 D4";
// 10100 and 10101: the seeded values, from slave 1.
const std::string kRight = "01 03 04 27 74 27 75 6A 8A";

ClientCase line_case(ClientScenario which, std::uint8_t code = 0) {
    for (const auto& c : client_line_cases())
        if (c.scenario == which && c.exception == code) return c;
    ADD_FAILURE() << "no such scenario";
    return {};
}

Clock::time_point at(int ms) {
    return Clock::time_point{} + std::chrono::milliseconds(ms);
}

struct Line {
    explicit Line(ClientScenario which, protocol::Framing framing = protocol::Framing::Rtu,
                  std::uint8_t code = 0)
        : exam(line_case(which, code), declared(), at(0), framing) {
        exam.opened(at(0));
    }
    static ClientDeclarations declared() {
        ClientDeclarations declared;
        declared.timeout = 500ms;
        declared.retries = 1;
        return declared;
    }
    void ask(const std::string& request, int ms) {
        const auto bytes = hex(request);
        exam.received(0, bytes, at(ms));
    }
    void ask_text(const std::string& request, int ms) {
        const std::vector<std::uint8_t> bytes(request.begin(), request.end());
        exam.received(0, bytes, at(ms));
    }
    std::vector<std::string> sent(int ms) {
        std::vector<std::string> lines;
        for (const auto& action : exam.due(at(ms)))
            lines.push_back(to_hex(action.bytes));
        return lines;
    }
    ClientExaminer exam;
};

using Lines = std::vector<std::string>;

TEST(ClientLineExaminer, AnotherSlavesAnswerComesFirstWithDecoysThenTheRightOne) {
    Line line(ClientScenario::WrongUnit);
    line.ask(kRequest, 0);
    EXPECT_EQ(line.sent(0), Lines{"02 03 04 9C A4 9C A5 0F FB"});
    EXPECT_EQ(line.sent(49), Lines{});
    EXPECT_EQ(line.sent(50), Lines{kRight});
    ASSERT_EQ(line.exam.requests().size(), 1U);
    EXPECT_EQ(line.exam.requests()[0].unit, 1);
    EXPECT_EQ(line.exam.requests()[0].address, 100);
}

TEST(ClientLineExaminer, ABadCrcFirstWithDecoysThenTheRightAnswerToTheNextRequest) {
    Line line(ClientScenario::BadCheck);
    line.ask(kRequest, 0);
    // The decoys' frame is whole but for the CRC's last byte (FB, sent as FA).
    EXPECT_EQ(line.sent(0), Lines{"01 03 04 9C A4 9C A5 3C FA"});
    line.ask(kRequest, 600);
    EXPECT_EQ(line.sent(600), Lines{kRight});
}

TEST(ClientLineExaminer, ABadLrcInAscii) {
    Line line(ClientScenario::BadCheck, protocol::Framing::Ascii);
    line.ask_text(":01030064000296\r\n", 0);
    const auto sent = line.exam.due(at(0));
    ASSERT_EQ(sent.size(), 1U);
    // The right LRC is 77; its last digit is changed.
    EXPECT_EQ(std::string(sent[0].bytes.begin(), sent[0].bytes.end()), ":0103049CA49CA570\r\n");
    line.ask_text(":01030064000296\r\n", 600);
    const auto right = line.exam.due(at(600));
    ASSERT_EQ(right.size(), 1U);
    EXPECT_EQ(std::string(right[0].bytes.begin(), right[0].bytes.end()), ":01030427742775C1\r\n");
}

TEST(ClientLineExaminer, ABroadcastIsNeverAnswered) {
    for (const auto which : {ClientScenario::Broadcast, ClientScenario::WrongUnit}) {
        Line line(which);
        line.ask("00 03 00 64 00 02 84 05", 0);
        EXPECT_EQ(line.sent(1000), Lines{});
        ASSERT_EQ(line.exam.requests().size(), 1U);
        EXPECT_EQ(line.exam.requests()[0].unit, 0);
    }
}

TEST(ClientLineExaminer, AnExceptionCarriesTheSlaveAddressAndACrc) {
    Line line(ClientScenario::Exception, protocol::Framing::Rtu, 0x02);
    line.ask(kRequest, 0);
    EXPECT_EQ(line.sent(0), Lines{"01 83 02 C0 F1"});
}

}  // namespace
}  // namespace mblab::conformance
