#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "server/journal.hpp"
#include "server/journaled_device.hpp"
#include "support/temp_dir.hpp"

namespace mblab::server {
namespace {

using test::TempDir;

std::vector<std::string> records_at(const std::filesystem::path& path) {
    auto records = read_journal(path);
    EXPECT_TRUE(records) << records.error();
    return records ? *records : std::vector<std::string>{};
}

TEST(Journal, EveryRecordIsWrittenBeforeItIsReportedDurable) {
    TempDir dir;
    const auto path = dir / "s.json.journal";
    std::atomic<int> durable{0};
    {
        auto journal = Journal::create(path);
        ASSERT_TRUE(journal) << journal.error();
        for (int i = 0; i < 100; ++i) {
            (*journal)->append("1 T 06000" + std::to_string(i % 10) + "0001", [&](bool written) {
                EXPECT_TRUE(written);
                ++durable;
            });
        }
    }
    EXPECT_EQ(durable.load(), 100);
    const auto records = records_at(path);
    ASSERT_EQ(records.size(), 100U);
    EXPECT_EQ(records[99], "1 T 0600090001");
}

TEST(Journal, RotateKeepsEarlierRecordsAsideUntilDropped) {
    TempDir dir;
    const auto path = dir / "s.json.journal";
    auto journal = Journal::create(path);
    ASSERT_TRUE(journal) << journal.error();
    (*journal)->append("1 T 0600010001", {});
    (void)(*journal)->rotate();
    (*journal)->append("1 T 0600020002", {});
    journal.value().reset();
    EXPECT_EQ(records_at(path), (std::vector<std::string>{"1 T 0600010001", "1 T 0600020002"}));
    auto again = Journal::create(dir / "t.journal");
    ASSERT_TRUE(again);
    (*again)->append("1 T 0600010001", {});
    const auto first = (*again)->rotate();
    (*again)->append("1 T 0600020002", {});
    (*again)->drop_old(first);
    again.value().reset();
    EXPECT_EQ(records_at(dir / "t.journal"), (std::vector<std::string>{"1 T 0600020002"}));
}

// A save that finishes after a later rotation covers only the records before its own: the
// records the later rotation moved aside stay until the later save.
TEST(Journal, AnOlderSaveDoesNotDropRecordsALaterRotationMovedAside) {
    TempDir dir;
    const auto path = dir / "s.json.journal";
    auto journal = Journal::create(path);
    ASSERT_TRUE(journal) << journal.error();
    (*journal)->append("1 T 0600010001", {});
    const auto first = (*journal)->rotate();
    (*journal)->append("1 T 0600020002", {});
    const auto second = (*journal)->rotate();
    (*journal)->drop_old(first);
    (*journal)->append("1 T 0600030003", {});
    journal.value().reset();
    EXPECT_EQ(records_at(path),
              (std::vector<std::string>{"1 T 0600010001", "1 T 0600020002", "1 T 0600030003"}));
    (void)second;
}

TEST(Journal, ARecordCutShortByACrashIsLeftOut) {
    TempDir dir;
    const auto path = dir / "s.json.journal";
    std::ofstream(path) << "1 T 0600010001\n1 T 06000";
    EXPECT_EQ(records_at(path), std::vector<std::string>{"1 T 0600010001"});
}

TEST(JournalRecord, RoundTripsAndRefusesOtherText) {
    const std::uint8_t pdu[] = {0x10, 0x00, 0x10, 0x00, 0x01, 0x02, 0xAB, 0xCD};
    const auto line = journal_record({7, device::Link::Serial}, pdu);
    EXPECT_EQ(line, "7 S 100010000102ABCD");
    device::RequestContext context;
    std::vector<std::uint8_t> request;
    ASSERT_TRUE(parse_journal_record(line, context, request));
    EXPECT_EQ(context.unit, 7);
    EXPECT_EQ(context.link, device::Link::Serial);
    EXPECT_EQ(request, std::vector<std::uint8_t>(std::begin(pdu), std::end(pdu)));
    for (const char* bad : {"", "x", "300 T 06", "1 X 06", "1 T 0", "1 T zz", "1 T"}) {
        EXPECT_FALSE(parse_journal_record(bad, context, request)) << bad;
    }
}

}  // namespace
}  // namespace mblab::server
