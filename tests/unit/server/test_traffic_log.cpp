#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "server/rotating_file.hpp"
#include "server/traffic_entry.hpp"
#include "server/traffic_log.hpp"
#include "support/hex.hpp"
#include "support/temp_dir.hpp"

namespace mblab::server {
namespace {

using test::file_text;
using test::hex;
using test::TempDir;

// 2026-11-27T10:15:02.250Z
constexpr auto kTime =
    std::chrono::system_clock::time_point(std::chrono::milliseconds(1'795'774'502'250LL));

TrafficEntry entry(const std::string& request, const std::string& response,
                   device::ReplyAction action = device::ReplyAction::Answer) {
    return {kTime,
            "192.0.2.7:50312",
            1,
            hex(request),
            action,
            hex(response),
            std::chrono::microseconds(41)};
}

TEST(TrafficText, ARegisterReadShowsItsRangeAndTheValuesReadBack) {
    EXPECT_EQ(traffic_text(entry("03 0000 0002", "03 04 0001 0102")),
              "2026-11-27T10:15:02.250Z 192.0.2.7:50312 unit 1 0x03 read holding registers "
              "address 0 quantity 2 -> values 1 258 (41 us)");
}

TEST(TrafficText, AnExceptionShowsItsCodeAndName) {
    EXPECT_EQ(traffic_text(entry("03 0FA0 0001", "83 02")),
              "2026-11-27T10:15:02.250Z 192.0.2.7:50312 unit 1 0x03 read holding registers "
              "address 4000 quantity 1 -> exception 02 (illegal data address) (41 us)");
}

TEST(TrafficText, AWriteShowsTheValuesWrittenAndLongOnesAreCut) {
    EXPECT_EQ(traffic_text(entry("06 0005 002A", "06 0005 002A")),
              "2026-11-27T10:15:02.250Z 192.0.2.7:50312 unit 1 0x06 write single register "
              "address 5 -> values 42 (41 us)");
    const auto line = traffic_text(
        entry("10 0000 000A 14 0001 0002 0003 0004 0005 0006 0007 0008 0009 000A", "10 0000 000A"));
    EXPECT_NE(line.find("quantity 10 -> values 1 2 3 4 5 6 7 8 ... (41 us)"), std::string::npos)
        << line;
}

TEST(TrafficText, SilenceAndDiagnosticsAreNamed) {
    EXPECT_NE(traffic_text(entry("08 0001 0000", "", device::ReplyAction::NoAnswer))
                  .find("0x08 diagnostics sub-function 1 (restart communications option) -> no "
                        "answer"),
              std::string::npos);
    const auto coils = traffic_text(entry("01 0000 0003", "01 01 05"));
    EXPECT_NE(coils.find("quantity 3 -> values 1 0 1 "), std::string::npos) << coils;
}

TEST(TrafficJson, TheFieldsAreThereToBeRead) {
    const auto json = nlohmann::json::parse(traffic_ndjson(entry("03 0FA0 0001", "83 02")));
    EXPECT_EQ(json["time"], "2026-11-27T10:15:02.250Z");
    EXPECT_EQ(json["peer"], "192.0.2.7:50312");
    EXPECT_EQ(json["unit"], 1);
    EXPECT_EQ(json["function"], 3);
    EXPECT_EQ(json["name"], "read holding registers");
    EXPECT_EQ(json["address"], 4000);
    EXPECT_EQ(json["quantity"], 1);
    EXPECT_EQ(json["answer"], "exception");
    EXPECT_EQ(json["exception"]["code"], 2);
    EXPECT_EQ(json["exception"]["name"], "illegal data address");
    EXPECT_EQ(json["latency_us"], 41);
    const auto read = nlohmann::json::parse(traffic_ndjson(entry("04 0001 0001", "04 02 FFFF")));
    EXPECT_EQ(read["values"], nlohmann::json::array({65535}));
    EXPECT_EQ(read["answer"], "values");
    EXPECT_FALSE(read.contains("exception"));
    EXPECT_EQ(traffic_ndjson(entry("03 0000 0001", "03 02 0000")).find('\n'), std::string::npos);
}

TEST(TrafficJson, ARequestThatDoesNotDecodeSaysWhy) {
    const auto json = nlohmann::json::parse(traffic_ndjson(entry("03 0000 0000", "83 03")));
    EXPECT_TRUE(json.contains("undecoded")) << json.dump();
    EXPECT_EQ(json["exception"]["code"], 3);
}

TEST(RotatingFile, ALineThatWouldPassTheLimitMovesTheFileAside) {
    TempDir dir;
    const auto path = dir / "traffic.log";
    auto file = RotatingFile::open(path, 25, nullptr);
    ASSERT_TRUE(file) << file.error();
    EXPECT_TRUE(file->write_line("0123456789"));
    EXPECT_TRUE(file->write_line("abcdefghij"));
    EXPECT_EQ(file_text(path), "0123456789\nabcdefghij\n");
    EXPECT_TRUE(file->write_line("third"));
    EXPECT_EQ(file_text(rotated_path(path)), "0123456789\nabcdefghij\n");
    EXPECT_EQ(file_text(path), "third\n");
    EXPECT_TRUE(file->write_line("0123456789"));
    EXPECT_TRUE(file->write_line("0123456789"));
    // The second rotation replaces the first file kept: two limits' worth at most.
    EXPECT_EQ(file_text(rotated_path(path)), "third\n0123456789\n");
    EXPECT_EQ(file_text(path), "0123456789\n");
}

TEST(RotatingFile, AnExistingFileCountsTowardsTheLimit) {
    TempDir dir;
    const auto path = dir / "traffic.log";
    {
        auto file = RotatingFile::open(path, 1000, nullptr);
        ASSERT_TRUE(file);
        file->write_line(std::string(20, 'x'));
    }
    auto file = RotatingFile::open(path, 30, nullptr);
    ASSERT_TRUE(file);
    EXPECT_EQ(file->size(), 21U);
    file->write_line("0123456789");
    EXPECT_EQ(file_text(path), "0123456789\n");
}

TEST(RotatingFile, AFullDiskIsOneWarningNeverAFailure) {
    const int fd = ::open("/dev/full", O_WRONLY | O_CLOEXEC);
    if (fd < 0) GTEST_SKIP() << "no /dev/full";
    std::vector<std::string> warnings;
    {
        auto file = RotatingFile::unrotated(fd, "/dev/full",
                                            [&](const std::string& w) { warnings.push_back(w); });
        EXPECT_FALSE(file.write_line("one"));
        EXPECT_FALSE(file.write_line("two"));
        EXPECT_FALSE(file.write_line("three"));
    }
    ::close(fd);
    ASSERT_EQ(warnings.size(), 1U);
    EXPECT_NE(warnings[0].find("No space left on device"), std::string::npos) << warnings[0];
}

TEST(RotatingFile, AFileThatCannotBeOpenedIsNamed) {
    const auto file = RotatingFile::open("/nonexistent-dir/traffic.log", 100, nullptr);
    ASSERT_FALSE(file);
    EXPECT_NE(file.error().find("/nonexistent-dir/traffic.log"), std::string::npos);
}

TEST(TrafficLog, TheRingKeepsTheLastEntriesAndReadersAskForWhatIsNew) {
    TrafficLog log(std::nullopt, TrafficFormat::Text, 3);
    for (int i = 0; i < 5; ++i)
        log.record(entry("03 000" + std::to_string(i) + " 0001", "03 02 0000"));
    std::uint64_t last = 0;
    auto kept = log.recent(0, last);
    EXPECT_EQ(last, 5U);
    ASSERT_EQ(kept.size(), 3U);
    EXPECT_EQ(kept.front().request, hex("03 0002 0001"));
    kept = log.recent(4, last);
    ASSERT_EQ(kept.size(), 1U);
    EXPECT_EQ(kept.front().request, hex("03 0004 0001"));
    EXPECT_TRUE(log.recent(5, last).empty());
}

TEST(TrafficLog, EachEntryIsOneLineInTheChosenFormat) {
    TempDir dir;
    const auto path = dir / "traffic.ndjson";
    auto file = RotatingFile::open(path, 0, nullptr);
    ASSERT_TRUE(file);
    {
        TrafficLog log(std::move(file.value()), TrafficFormat::Ndjson, 0);
        log.record(entry("03 0000 0001", "03 02 0007"));
        log.record(entry("03 0FA0 0001", "83 02"));
    }
    const auto text = file_text(path);
    const auto newline = text.find('\n');
    ASSERT_NE(newline, std::string::npos);
    EXPECT_EQ(nlohmann::json::parse(text.substr(0, newline))["values"][0], 7);
    EXPECT_EQ(nlohmann::json::parse(text.substr(newline + 1))["exception"]["code"], 2);
}

}  // namespace
}  // namespace mblab::server
