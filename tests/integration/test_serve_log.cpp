// `mblab serve --log`: the real binary serves, the mblab client asks, and the log it writes (a
// file, standard error, the dashboard's /api/traffic) is read back: the device's answers and
// those the session gives itself, with the client's address over Modbus/TCP and RTU over TCP.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "blocking_client.hpp"
#include "http_serve.hpp"
#include "support/temp_dir.hpp"

namespace mblab::test {
namespace {

using ::testing::HasSubstr;
using ::testing::MatchesRegex;

std::vector<nlohmann::json> ndjson_lines(const std::string& text) {
    std::vector<nlohmann::json> out;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) {
        auto parsed = nlohmann::json::parse(line, nullptr, false);
        EXPECT_FALSE(parsed.is_discarded()) << "not JSON: " << line;
        out.push_back(std::move(parsed));
    }
    return out;
}

TEST(ServeLog, EachRequestIsOneNdjsonLineWithItsFieldsAndAnswer) {
    if (!have("/usr/bin/curl")) GTEST_SKIP() << "no curl";
    TempDir dir;
    const auto path = dir / "traffic.ndjson";
    std::vector<nlohmann::json> lines;
    {
        HttpServe serve({"--log=" + path.string(), "--log-format", "ndjson"});
        ASSERT_FALSE(serve.modbus().empty());
        change(serve, "POST", "/api/units/1/faults",
               R"({"action":"exception","exception":4,"functions":[6]})");
        EXPECT_EQ(run_mblab({"read", serve.modbus(), "holding", "10", "2"}).status, 0);
        EXPECT_EQ(run_mblab({"write", serve.modbus(), "register", "3", "42"}).status, 1);
        // The dashboard's ring holds the same entries.
        const auto traffic = curl({serve.http() + "/api/traffic?after=1"});
        EXPECT_THAT(traffic.out, HasSubstr("\"server device failure\"")) << traffic.out;
        EXPECT_THAT(traffic.out, HasSubstr("\"last\":2")) << traffic.out;
        EXPECT_THAT(traffic.out, ::testing::Not(HasSubstr("\"read holding registers\"")));
        lines = ndjson_lines(file_text(path));
    }
    ASSERT_EQ(lines.size(), 2U);
    const auto& read = lines[0];
    EXPECT_EQ(read["function"], 3);
    EXPECT_EQ(read["name"], "read holding registers");
    EXPECT_EQ(read["unit"], 1);
    EXPECT_EQ(read["address"], 10);
    EXPECT_EQ(read["quantity"], 2);
    EXPECT_EQ(read["values"].size(), 2U);
    EXPECT_EQ(read["answer"], "values");
    EXPECT_THAT(read["peer"].get<std::string>(), MatchesRegex("127\\.0\\.0\\.1:[0-9]+"));
    EXPECT_TRUE(read["latency_us"].is_number_integer());
    EXPECT_THAT(read["time"].get<std::string>(),
                MatchesRegex("[0-9]{4}-[0-9]{2}-[0-9]{2}T[0-9:.]+Z"));
    const auto& write = lines[1];
    EXPECT_EQ(write["name"], "write single register");
    EXPECT_EQ(write["values"], nlohmann::json::array({42}));
    EXPECT_EQ(write["answer"], "exception");
    EXPECT_EQ(write["exception"]["code"], 4);
    EXPECT_EQ(write["exception"]["name"], "server device failure");
}

TEST(ServeLog, AnswersTheSessionGivesItselfAreLoggedToo) {
    if (!have("/usr/bin/curl")) GTEST_SKIP() << "no curl";
    TempDir dir;
    const auto path = dir / "traffic.ndjson";
    std::vector<nlohmann::json> lines;
    {
        HttpServe serve({"--log=" + path.string(), "--log-format", "ndjson", "--max-outstanding",
                         "1", "--frame-timeout", "50ms"});
        ASSERT_FALSE(serve.modbus().empty());
        // An answer held back fills the connection's one place: the request behind it is
        // answered 06 by the session, which the device never sees.
        change(serve, "POST", "/api/units/1/faults",
               R"({"action":"delay","delay_ms":300,"functions":[3]})");
        const auto& url = serve.modbus();
        BlockingClient client(
            static_cast<std::uint16_t>(std::stoi(url.substr(url.rfind(':') + 1))));
        ASSERT_TRUE(client.connected());
        client.send_hex("00 01 00 00 00 06 01 03 00 00 00 01 00 02 00 00 00 06 01 04 00 07 00 02");
        EXPECT_THAT(client.read_adu(), HasSubstr("00 01 00 00 00 05 01 03 02"));
        EXPECT_EQ(client.read_adu(), "00 02 00 00 00 03 01 84 06");
        // A frame whose bytes stop coming: answered 03 by the session once they stop.
        client.send_hex("00 03 00 00 00 06 01 03 00");
        EXPECT_EQ(client.read_adu(), "00 03 00 00 00 03 01 83 03");
        lines = ndjson_lines(file_text(path));
    }
    ASSERT_EQ(lines.size(), 3U);
    const auto answered = [&](int function) {
        for (const auto& line : lines)
            if (line["function"] == function && line["answer"] == "exception") return line;
        return nlohmann::json();
    };
    const auto busy = answered(4);
    EXPECT_EQ(busy["exception"]["code"], 6) << busy.dump();
    EXPECT_EQ(busy["address"], 7);
    EXPECT_EQ(busy["quantity"], 2);
    EXPECT_THAT(busy["peer"].get<std::string>(), MatchesRegex("127\\.0\\.0\\.1:[0-9]+"));
    const auto unfinished = answered(3);
    EXPECT_EQ(unfinished["exception"]["code"], 3) << unfinished.dump();
    EXPECT_TRUE(unfinished.contains("undecoded")) << unfinished.dump();
}

TEST(ServeLog, AnRtuOverTcpClientIsLoggedByItsOwnAddress) {
    ChildProcess serve(
        {MBLAB_BINARY, "serve", "reference", "--listen", "rtu+tcp://127.0.0.1:0", "--log"});
    const auto target = modbus_target(serve);
    ASSERT_FALSE(target.empty());
    EXPECT_EQ(run_mblab({"read", "rtu+" + target, "holding", "0"}).status, 0);
    serve.signal(SIGTERM);
    EXPECT_EQ(serve.wait_exit(10s), 0);
    // The client's address and port, not the address listened on.
    const auto listened = target.substr(std::string("tcp://").size());
    const auto log = serve.drain_stderr();
    EXPECT_THAT(log,
                MatchesRegex("[0-9TZ:.-]+ 127\\.0\\.0\\.1:[0-9]+ unit 1 0x03 read holding "
                             "registers address 0 quantity 1 -> values [0-9]+ \\([0-9]+ us\\)\n"));
    EXPECT_THAT(log, ::testing::Not(HasSubstr(" " + listened + " ")));
}

TEST(ServeLog, ABareLogWritesTextLinesToStandardError) {
    ChildProcess serve(
        {MBLAB_BINARY, "serve", "reference", "--listen", "tcp://127.0.0.1:0", "--log"});
    const auto target = modbus_target(serve);
    ASSERT_FALSE(target.empty());
    EXPECT_EQ(run_mblab({"read", target, "input", "0", "20"}).status, 0);
    serve.signal(SIGTERM);
    EXPECT_EQ(serve.wait_exit(10s), 0);
    EXPECT_THAT(serve.drain_stderr(),
                MatchesRegex("[0-9TZ:.-]+ 127\\.0\\.0\\.1:[0-9]+ unit 1 0x04 read input registers "
                             "address 0 quantity 20 -> values( [0-9]+){8} \\.\\.\\. \\([0-9]+ "
                             "us\\)\n"));
}

TEST(ServeLog, TheFileIsRotatedAtItsLimitSoItNeverGrowsPastIt) {
    TempDir dir;
    const auto path = dir / "traffic.log";
    {
        HttpServe serve({"--log", path.string(), "--log-max-size", "1k"});
        ASSERT_FALSE(serve.modbus().empty());
        for (int i = 0; i < 20; ++i)
            ASSERT_EQ(run_mblab({"read", serve.modbus(), "coils", std::to_string(i)}).status, 0);
    }
    const auto kept = std::filesystem::path(path.string() + ".1");
    ASSERT_TRUE(std::filesystem::exists(kept));
    EXPECT_LE(std::filesystem::file_size(path), 1024U);
    EXPECT_LE(std::filesystem::file_size(kept), 1024U);
    // Whole lines on both sides of the cut: the newest is last in the current file.
    EXPECT_THAT(file_text(path), HasSubstr("read coils address 19 quantity 1 -> values "));
    EXPECT_EQ(file_text(kept).back(), '\n');
}

TEST(ServeLog, AFullDiskIsOneWarningAndTheDeviceKeepsAnswering) {
    if (!std::filesystem::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
    ChildProcess serve({MBLAB_BINARY, "serve", "--listen", "tcp://127.0.0.1:0", "--log=/dev/full"});
    const auto target = modbus_target(serve);
    ASSERT_FALSE(target.empty());
    for (int i = 0; i < 3; ++i)
        EXPECT_EQ(run_mblab({"read", target, "holding", "0"}).status, 0);
    serve.signal(SIGTERM);
    EXPECT_EQ(serve.wait_exit(10s), 0);
    EXPECT_EQ(serve.drain_stderr(),
              "mblab serve: --log /dev/full: cannot write: No space left on device; log lines are "
              "dropped until it works again\n");
}

TEST(ServeLog, AFileThatCannotBeWrittenIsAUsageError) {
    const auto ran = run_mblab({"serve", "--log", "/nonexistent-dir/traffic.log"});
    EXPECT_EQ(ran.status, 2);
    EXPECT_EQ(ran.err,
              "mblab serve: --log /nonexistent-dir/traffic.log: No such file or directory\n");
}

}  // namespace
}  // namespace mblab::test
