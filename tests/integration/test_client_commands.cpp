#include <nlohmann/json.hpp>
#include <regex>

#include "support/hex.hpp"
#include "support/malicious_server.hpp"
#include "test_client_support.hpp"

// `mblab diag`, `devid`, `raw`, `watch` and --decode against the reference device.
namespace mblab::test {
namespace {

using ClientCommands = ReferenceCliTest;

TEST_F(ClientCommands, DiagEchoesQueryData) {
    auto ran = mblab("diag", {"query-data", "0x1234", "0xABCD"});
    EXPECT_EQ(ran.status, 0) << ran.err;
    EXPECT_EQ(ran.out, "echoed 4 bytes: 12 34 AB CD\n");
    EXPECT_EQ(mblab("diag", {"0", "7"}).out, "echoed 2 bytes: 00 07\n");
}

TEST_F(ClientCommands, DiagPrintsCountersByName) {
    EXPECT_EQ(mblab("diag", {"diagnostic-register"}).out, "diagnostic register: 0x0000\n");
    auto ran = mblab("diag", {"counters"});
    EXPECT_EQ(ran.status, 0) << ran.err;
    const std::regex shape(
        "bus-message-count: \\d+\n"
        "bus-communication-error-count: 0\n"
        "bus-exception-error-count: \\d+\n"
        "server-message-count: \\d+\n"
        "server-no-response-count: 0\n"
        "server-nak-count: 0\n"
        "server-busy-count: 0\n"
        "bus-character-overrun-count: 0\n");
    EXPECT_TRUE(std::regex_match(ran.out, shape)) << ran.out;
    auto one = mblab("diag", {"0x0E", "--json"});
    auto document = nlohmann::json::parse(one.out);
    EXPECT_EQ(document["name"], "return server message count");
    EXPECT_TRUE(document["value"].is_number());
}

TEST_F(ClientCommands, DiagClearsAndRestarts) {
    EXPECT_EQ(mblab("diag", {"clear-counters"}).out, "counters and diagnostic register cleared\n");
    EXPECT_EQ(mblab("diag", {"restart-communications", "0xFF00"}).out,
              "communications restarted\n");
    auto refused = mblab("diag", {"restart-communications", "0x1234"});
    EXPECT_EQ(refused.status, 2);
    EXPECT_EQ(refused.err.rfind("mblab diag: diagnostics: ", 0), 0U) << refused.err;
}

TEST_F(ClientCommands, DiagListenOnlyUntilRestart) {
    EXPECT_EQ(mblab("diag", {"force-listen-only"}).out,
              "sent force listen only mode (never answered): the device now answers nothing until "
              "restart-communications\n");
    auto silent = mblab("read", {"holding", "0", "--timeout", "300"});
    EXPECT_EQ(silent.status, 1);
    // [APP] 6.8.1: a port in listen only mode restarts without answering; that silence is the
    // right answer, which the next request (answered again) confirms.
    auto restart = mblab("diag", {"restart-communications", "--timeout", "300"});
    EXPECT_EQ(restart.status, 0) << restart.err;
    EXPECT_EQ(restart.out,
              "communications restarted: no answer, as a device in listen only mode gives none "
              "(Modbus Application Protocol 6.8.1); it answers again\n");
    EXPECT_EQ(restart.err, "");
    // Out of listen only mode: the next restart is answered.
    EXPECT_EQ(mblab("diag", {"restart-communications", "--timeout", "300"}).out,
              "communications restarted\n");
    EXPECT_EQ(mblab("read", {"holding", "0"}).status, 0);
}

TEST_F(ClientCommands, DevidReadsTheBasicObjects) {
    auto ran = mblab("devid", {});
    EXPECT_EQ(ran.status, 0) << ran.err;
    EXPECT_EQ(ran.out,
              "conformity level 0x83 (extended, individual access)\n"
              "0x00  vendor name           mblab\n"
              "0x01  product code          MBLAB-REF\n"
              "0x02  major minor revision  0.1.0\n");
    EXPECT_EQ(mblab("devid", {"product-name"}).out,
              "conformity level 0x83 (extended, individual access)\n"
              "0x04  product name  mblab reference device\n");
}

TEST_F(ClientCommands, DevidFollowsMoreFollowsAcrossTransactions) {
    // Seven objects of 200 bytes: at most one fits an answer, so the device needs several.
    const std::string value(200, 'x');
    std::string profile =
        "[[unit]]\nid = 1\n[[unit.holding_registers]]\nstart = 0\n"
        "[unit.identification]\n";
    for (const char* key : {"vendor", "product_code", "revision", "vendor_url", "product_name",
                            "model", "user_application"}) {
        profile += std::string(key) + " = \"" + value + "\"\n";
    }
    auto loaded = device::load_profile_text(profile, "long-objects");
    ASSERT_TRUE(loaded) << loaded.error();
    server_.reset();
    device_ = std::move(loaded.value());
    start_server(*device_);
    auto ran = mblab("devid", {"regular", "--json"});
    EXPECT_EQ(ran.status, 0) << ran.err;
    auto document = nlohmann::json::parse(ran.out);
    EXPECT_EQ(document["transactions"], 7);
    ASSERT_EQ(document["objects"].size(), 7U);
    for (std::size_t i = 0; i < 7; ++i) {
        EXPECT_EQ(document["objects"][i]["id"], i);
        EXPECT_EQ(document["objects"][i]["value"], value);
    }
}

TEST_F(ClientCommands, RawSendsAnyPduAndDecodesTheAnswer) {
    auto ran = mblab("raw", {"03", "00 00", "0x0002"});
    EXPECT_EQ(ran.status, 0) << ran.err;
    EXPECT_EQ(ran.out,
              "request  03 00 00 00 02\n"
              "         function 0x03 read holding registers: starting address 0 (0x0000), "
              "quantity 2\n"
              "answer   03 04 53 45 4D 49\n"
              "         function 0x03 read holding registers: byte count 4, registers 0x5345 "
              "0x4D49\n");
    // Requests no other command would send go out as they are.
    auto unknown = mblab("raw", {"25 00 01 00 01"});
    EXPECT_EQ(unknown.status, 1);
    EXPECT_EQ(unknown.out,
              "request  25 00 01 00 01\n"
              "         function 0x25: data 00 01 00 01\n"
              "answer   A5 01\n"
              "         function 0xA5 exception to function 0x25: exception code 01 (illegal "
              "function)\n");
    EXPECT_EQ(unknown.err,
              "mblab raw: exception 01 illegal function: the device does not "
              "support function 0x25\n");
    auto quantity = mblab("raw", {"03 00 00 FF FF"});
    expect_failed(quantity, 1,
                  "mblab raw: exception 03 illegal data value: a value or length in "
                  "the request is not allowed\n");
}

TEST_F(ClientCommands, WatchPrintsEveryPollAsPlainLines) {
    auto ran = mblab("watch", {"holding", "1", "2", "--count", "3", "--interval", "10"});
    EXPECT_EQ(ran.status, 0) << ran.err;
    const std::string table =
        "address     raw     u16\n"
        "1 (0x0001)  0x4D49  19785\n"
        "2 (0x0002)  0x5F72  24434\n";
    EXPECT_EQ(ran.out, "poll 1\n" + table + "poll 2\n" + table + "poll 3\n" + table +
                           "3 polls: 3 answered, 0 timeouts, 0 exceptions, 0 other errors\n");
}

TEST(ClientWatch, CountsExceptionsAndTimeoutsAndGoesOn) {
    MaliciousServer server([](std::span<const std::uint8_t> request, int index) {
        if (index == 1) return Answer{mbap_answer(request, hex("83 02"))};
        if (index == 2) return Answer{};
        return Answer{mbap_answer(request, hex("03 02 00 05"))};
    });
    const auto port = server.start();
    auto ran = run_mblab({"watch", tcp_target(port), "holding", "7", "--count", "4", "--interval",
                          "10", "--timeout", "1000"});
    EXPECT_EQ(ran.status, 1);
    const std::string table = "address     raw     u16\n7 (0x0007)  0x0005  5\n";
    EXPECT_EQ(ran.out, "poll 1\n" + table +
                           "poll 2\nexception 02 illegal data address: 0x0007 is not on this "
                           "device\n"
                           "poll 3\nno answer from " +
                           tcp_target(port) + " (unit 1) within 1000 ms\n" + "poll 4\n" + table +
                           "4 polls: 2 answered, 1 timeout, 1 exception, 0 other errors\n");
    EXPECT_EQ(ran.err, "mblab watch: 2 of 4 polls failed\n");
}

TEST_F(ClientCommands, WatchRedrawsInPlaceOnATerminal) {
    // script(1) gives the command a pseudo-terminal as stdout (and turns \n into \r\n).
    const std::string command =
        std::string(MBLAB_BINARY) + " watch " + target() + " holding 0 1 --count 2 --interval 10";
    ChildProcess child({"/usr/bin/script", "-qec", command, "/dev/null"});
    std::string out;
    while (auto line = child.read_stdout_line(std::chrono::seconds(30)))
        out += *line + "\n";
    EXPECT_EQ(child.wait_exit(std::chrono::seconds(30)), 0);
    const std::string title = target() +
                              " unit 1: holding registers 0 (0x0000), 1 u16 value "
                              "every 10 ms (Ctrl-C stops)\r\n";
    const std::string table = "address     raw     u16\r\n0 (0x0000)  0x5345  21317\r\n";
    EXPECT_EQ(out, title + "1 poll: 1 answered, 0 timeouts, 0 exceptions, 0 other errors\r\n" +
                       table +
                       // Up four lines to the title, clear below, draw again.
                       "\x1b[4F\x1b[J" + title +
                       "2 polls: 2 answered, 0 timeouts, 0 exceptions, 0 other errors\r\n" + table +
                       "2 polls: 2 answered, 0 timeouts, 0 exceptions, 0 other errors\r\n");
}

TEST_F(ClientCommands, WatchJsonIsOneDocumentAtTheEnd) {
    auto ran = mblab("watch", {"coils", "0", "2", "--count", "2", "--interval", "10", "--json"});
    EXPECT_EQ(ran.status, 0) << ran.err;
    auto document = nlohmann::json::parse(ran.out);
    EXPECT_EQ(document["polls"].size(), 2U);
    EXPECT_EQ(document["polls"][1]["values"][1]["address"], 1);
    EXPECT_EQ(document["summary"]["answered"], 2);
}

TEST_F(ClientCommands, DecodeDepths) {
    const std::string request_fields =
        "function 0x03 read holding registers: starting address 2 (0x0002), quantity 1\n";
    const std::string answer_fields =
        "function 0x03 read holding registers: byte count 2, registers 0x5F72\n";
    auto app = mblab("read", {"holding", "2", "--decode", "app"});
    EXPECT_EQ(app.err, ">   " + request_fields + "<   " + answer_fields);
    auto frame = mblab("read", {"holding", "2", "--decode", "frame"});
    EXPECT_EQ(frame.err,
              ">   MBAP transaction id 1 (0x0001), protocol id 0, length 6, unit id 1\n"
              ">   " +
                  request_fields +
                  "<   MBAP transaction id 1 (0x0001), protocol id 0, length 5, unit id 1\n"
                  "<   " +
                  answer_fields);
    auto bytes = mblab("read", {"holding", "2", "--decode", "bytes", "--unit", "0"});
    EXPECT_EQ(bytes.err,
              "> 00 01 00 00 00 06 00 03 00 02 00 01\n"
              ">   MBAP transaction id 1 (0x0001), protocol id 0, length 6, unit id 0\n"
              ">   " +
                  request_fields +
                  "< 00 01 00 00 00 05 00 03 02 5F 72\n"
                  "<   MBAP transaction id 1 (0x0001), protocol id 0, length 5, unit id 0\n"
                  "<   " +
                  answer_fields);
    EXPECT_EQ(bytes.out, "address     raw     u16\n2 (0x0002)  0x5F72  24434\n");
}

}  // namespace
}  // namespace mblab::test
