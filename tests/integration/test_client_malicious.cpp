#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <atomic>
#include <regex>

#include "support/hex.hpp"
#include "support/malicious_server.hpp"
#include "test_client_support.hpp"

// A hostile device never crashes the client (CVE-2023-26793): every broken answer ends in one
// clear line and exit status 1, asserted exactly.
namespace mblab::test {
namespace {

using ::testing::HasSubstr;

using namespace std::chrono_literals;

// Runs `mblab COMMAND TARGET ARGS...` against a server answering every request with `make`.
Ran run_against(const std::function<Answer(std::span<const std::uint8_t>)>& make,
                std::vector<std::string> command) {
    MaliciousServer server(
        [&](std::span<const std::uint8_t> request, int) { return make(request); });
    const auto port = server.start();
    EXPECT_NE(port, 0);
    command.insert(command.begin() + 1, tcp_target(port));
    return run_mblab(command);
}

// Reads holding 0..1; answers are expected well within `timeout_ms` unless the script withholds
// them, so a loaded machine cannot turn an answer into a timeout.
Ran read_against(const std::function<Answer(std::span<const std::uint8_t>)>& make,
                 std::vector<std::string> extra = {}, const std::string& timeout_ms = "3000") {
    std::vector<std::string> command = {"read", "holding", "0", "2", "--timeout", timeout_ms};
    command.insert(command.end(), extra.begin(), extra.end());
    return run_against(make, command);
}

// The request's own transaction id and unit, with `pdu` after them and a correct length.
Answer answer_pdu(std::span<const std::uint8_t> request, const char* pdu) {
    return {mbap_answer(request, hex(pdu))};
}

// `mblab devid` against a device whose every answer is `pdu`.
Ran devid_against(const char* pdu) {
    return run_against([pdu](auto request) { return answer_pdu(request, pdu); },
                       {"devid", "--timeout", "3000"});
}

void expect_bad(const Ran& ran, const std::string& line) {
    EXPECT_EQ(ran.out, "");
    expect_failed(ran, 1, "mblab read: " + line + "\n");
}

TEST(ClientMalicious, AGoodAnswerFromTheScriptIsRead) {
    auto ran = read_against([](auto request) { return answer_pdu(request, "03 04 00 2A 00 2B"); });
    EXPECT_EQ(ran.status, 0) << ran.err;
    EXPECT_EQ(ran.out, "address     raw     u16\n0 (0x0000)  0x002A  42\n1 (0x0001)  0x002B  43\n");
}

TEST(ClientMalicious, MbapLengthShorterThanThePdu) {
    // Length 4 cuts the PDU after the byte count: 03 04 00.
    auto ran = read_against([](auto request) {
        return Answer{mbap_frame(1, 0, 4, request[6], hex("03 04 00 2A 00 2B"))};
    });
    expect_bad(ran,
               "bad answer: read holding registers: byte count: must equal the number of "
               "bytes that follow it");
}

TEST(ClientMalicious, MbapLengthLongerThanWhatComes) {
    auto ran = read_against(
        [](auto request) {
            return Answer{mbap_frame(1, 0, 20, request[6], hex("03 04 00 2A 00 2B"))};
        },
        {}, "300");
    EXPECT_EQ(ran.status, 1);
    EXPECT_THAT(ran.err, HasSubstr("within 300 ms (13 bytes of a frame came)\n"));
}

TEST(ClientMalicious, MbapLengthsNoFrameCanHave) {
    for (std::uint16_t length : {0, 255, 0xFFFF}) {
        auto ran = read_against([length](auto request) {
            return Answer{mbap_frame(1, 0, length, request[6], hex("03 04 00 2A 00 2B"))};
        });
        expect_bad(ran, "bad answer: MBAP length " + std::to_string(length) +
                            " cannot describe a frame (must be 2..254)");
    }
}

TEST(ClientMalicious, MbapLengthOneHasNoFunctionCode) {
    auto ran =
        read_against([](auto request) { return Answer{mbap_frame(1, 0, 1, request[6], {})}; });
    expect_bad(ran, "bad answer: MBAP length 1 leaves no room for a function code");
}

TEST(ClientMalicious, ByteCountBeyondTheFrame) {
    auto ran = read_against([](auto request) { return answer_pdu(request, "03 FA 00 2A 00 2B"); });
    expect_bad(ran,
               "bad answer: read holding registers: byte count: must equal the number of "
               "bytes that follow it");
    auto odd = read_against([](auto request) { return answer_pdu(request, "03 FF 00 2A 00 2B"); });
    expect_bad(odd,
               "bad answer: read holding registers: byte count: must be even, 2..250 "
               "(1..125 registers)");
}

TEST(ClientMalicious, FewerRegistersThanAskedFor) {
    auto ran = read_against([](auto request) { return answer_pdu(request, "03 02 00 2A"); });
    expect_bad(ran, "bad answer: read holding registers: 1 register, expected 2");
}

TEST(ClientMalicious, WrongFunctionCode) {
    auto ran = read_against([](auto request) { return answer_pdu(request, "04 04 00 2A 00 2B"); });
    expect_bad(ran,
               "bad answer: function code is 0x04 (read input registers), expected 0x03 "
               "(read holding registers)");
}

// TCPG 4.4.1.1: discarded, and the wait goes on until the timeout, which names it.
TEST(ClientMalicious, DifferentTransactionId) {
    auto ran = read_against(
        [](auto request) {
            return Answer{mbap_frame(0x1234, 0, 7, request[6], hex("03 04 00 2A 00 2B"))};
        },
        {"--no-probe"}, "300");
    EXPECT_EQ(ran.status, 1);
    EXPECT_THAT(ran.err, HasSubstr(" (unit 1) within 300 ms; discarded an answer under transaction "
                                   "id 0x1234, expected 0x0001\n"));
}

TEST(ClientMalicious, OtherProtocolIdAndUnit) {
    auto protocol = read_against([](auto request) {
        return Answer{mbap_frame(1, 1, 7, request[6], hex("03 04 00 2A 00 2B"))};
    });
    expect_bad(protocol, "bad answer: MBAP protocol id is 0x0001, expected 0x0000 (Modbus)");
    auto unit =
        read_against([](auto) { return Answer{mbap_frame(1, 0, 7, 9, hex("03 04 00 2A 00 2B"))}; },
                     {"--no-probe"}, "300");
    EXPECT_EQ(unit.status, 1);
    EXPECT_THAT(
        unit.err,
        HasSubstr(" (unit 1) within 300 ms; discarded an answer from unit 9, expected 1\n"));
}

TEST(ClientMalicious, ExceptionWithTrailingBytes) {
    auto ran = read_against([](auto request) { return answer_pdu(request, "83 02 00"); });
    expect_bad(ran,
               "bad answer: read holding registers: PDU length: bytes follow the last field "
               "of the PDU");
}

TEST(ClientMalicious, SilenceAndClosedConnections) {
    auto silent = read_against([](auto) { return Answer{}; }, {}, "300");
    EXPECT_EQ(silent.status, 1);
    EXPECT_TRUE(std::regex_search(silent.err,
                                  std::regex(" \\(unit 1\\) within 300 ms; units 255 and 0 did not "
                                             "answer either \\(3 probe reads, [0-9]+ ms; "
                                             "--no-probe skips them\\)\n")))
        << silent.err;
    // --no-probe: the unanswered request alone, and the message says nothing of other units.
    std::atomic<int> requests{0};
    auto unprobed = read_against(
        [&requests](auto) {
            ++requests;
            return Answer{};
        },
        {"--no-probe"}, "300");
    EXPECT_EQ(unprobed.status, 1);
    EXPECT_TRUE(unprobed.err.ends_with(" (unit 1) within 300 ms\n")) << unprobed.err;
    EXPECT_EQ(requests.load(), 1);
    auto closed = read_against([](auto) { return Answer{{}, 0ms, true}; });
    expect_bad(closed, "the device closed the connection without answering");
    auto half = read_against([](auto request) {
        auto frame = mbap_answer(request, hex("03 04 00 2A 00 2B"));
        frame.resize(9);
        return Answer{frame, 0ms, true};
    });
    expect_bad(half, "the device closed the connection after 9 bytes of an answer");
}

TEST(ClientMalicious, AFloodOfBytes) {
    auto ran = read_against([](auto) { return Answer{std::vector<std::uint8_t>(100000, 0xFF)}; });
    expect_bad(ran, "bad answer: MBAP length 65535 cannot describe a frame (must be 2..254)");
}

TEST(ClientMalicious, DecodeShowsTheBadFrame) {
    auto ran = read_against([](auto request) { return answer_pdu(request, "03 FA 00 2A"); },
                            {"--decode", "bytes"});
    expect_failed(
        ran, 1,
        "> 00 01 00 00 00 06 01 03 00 00 00 02\n"
        ">   MBAP transaction id 1 (0x0001), protocol id 0, length 6, unit id 1\n"
        ">   function 0x03 read holding registers: starting address 0 (0x0000), quantity 2\n"
        "< 00 01 00 00 00 05 01 03 FA 00 2A\n"
        "<   MBAP transaction id 1 (0x0001), protocol id 0, length 5, unit id 1\n"
        "<   function 0x03 read holding registers: does not decode: byte count: must equal "
        "the number of bytes that follow it\n"
        "mblab read: bad answer: read holding registers: byte count: must equal the number "
        "of bytes that follow it\n");
}

TEST(ClientMalicious, DeviceIdentificationThatNeverEnds) {
    // "More follows" with a next object id that goes back: the client stops instead of looping.
    auto ran = devid_against("2B 0E 01 01 FF 00 01 00 01 41");
    expect_failed(ran, 1,
                  "mblab devid: bad answer: read device identification: more follows, but "
                  "the next object id 0x00 does not come after the objects sent\n");
}

TEST(ClientMalicious, DeviceIdentificationObjectLongerThanTheFrame) {
    auto ran = devid_against("2B 0E 01 01 00 00 01 00 F0 41");
    EXPECT_EQ(ran.status, 1);
    EXPECT_EQ(ran.err.rfind("mblab devid: bad answer: encapsulated interface transport: ", 0), 0U)
        << ran.err;
}

TEST(ClientMalicious, RetriesSkipTheLateAnswerOfATimedOutRequest) {
    // The first request is answered after the client gave up on it, just before the answer to
    // the retry: the client must take the retry's answer, not the late one.
    MaliciousServer server([](std::span<const std::uint8_t> request, int index) {
        if (index == 0) return Answer{};
        auto late = mbap_frame(1, 0, 7, request[6], hex("03 04 00 01 00 01"));
        auto right = mbap_answer(request, hex("03 04 00 2A 00 2B"));
        late.insert(late.end(), right.begin(), right.end());
        return Answer{late};
    });
    const auto port = server.start();
    auto ran = run_mblab({"read", tcp_target(port), "holding", "0", "2", "--timeout", "1000",
                          "--retries", "1", "--decode", "app"});
    EXPECT_EQ(ran.status, 0) << ran.err;
    EXPECT_EQ(ran.out, "address     raw     u16\n0 (0x0000)  0x002A  42\n1 (0x0001)  0x002B  43\n");
    EXPECT_NE(ran.err.find("* retry 1 of 1 after: no answer from " + tcp_target(port) +
                           " (unit 1) within 1000 ms\n"),
              std::string::npos)
        << ran.err;
    EXPECT_THAT(ran.err, HasSubstr("* skipped a late answer to transaction 0x0001\n"));
}

TEST(ClientMalicious, RetriesGiveUpAfterTheLastTry) {
    MaliciousServer server([](std::span<const std::uint8_t>, int) { return Answer{}; });
    const auto port = server.start();
    auto ran =
        run_mblab({"read", tcp_target(port), "holding", "0", "--timeout", "200", "--retries", "2"});
    EXPECT_EQ(ran.status, 1);
    // The unit asked is named, and it, then units 255 and 0, are asked once each with a harmless
    // read.
    EXPECT_TRUE(std::regex_match(
        ran.err, std::regex("mblab read: no answer from " + tcp_target(port) +
                            " \\(unit 1\\) within 200 ms \\(3 tries\\); units 255 and 0 did not "
                            "answer either \\(3 probe reads, [0-9]+ ms; --no-probe skips "
                            "them\\)\n")))
        << ran.err;
    EXPECT_EQ(server.requests(), 6);
}

TEST(ClientMalicious, NoAnswerNamesTheUnitThatDoesAnswer) {
    MaliciousServer server([](std::span<const std::uint8_t> request, int) {
        if (request[6] != 0xFF) return Answer{};
        return Answer{mbap_answer(request, hex("03 02 00 07"))};
    });
    const auto port = server.start();
    auto ran = run_mblab({"write", tcp_target(port), "register", "5", "9", "--timeout", "200"});
    EXPECT_EQ(ran.status, 1);
    EXPECT_TRUE(std::regex_match(
        ran.err, std::regex("mblab write: no answer from " + tcp_target(port) +
                            " \\(unit 1\\) within 200 ms; the device answers unit 255: try "
                            "--unit 255 \\(2 probe reads, [0-9]+ ms; --no-probe skips them\\)\n")))
        << ran.err;
}

TEST(ClientMalicious, RetriesReconnectAfterTheDeviceClosed) {
    MaliciousServer server([](std::span<const std::uint8_t> request, int index) {
        if (index == 0) return Answer{{}, 0ms, true};
        return answer_pdu(request, "03 02 00 07");
    });
    const auto port = server.start();
    auto ran = run_mblab({"read", tcp_target(port), "holding", "0", "--retries", "1"});
    EXPECT_EQ(ran.status, 0) << ran.err;
    EXPECT_EQ(ran.out, "address     raw     u16\n0 (0x0000)  0x0007  7\n");
}

}  // namespace
}  // namespace mblab::test
