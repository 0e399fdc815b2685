#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <future>
#include <string>
#include <vector>

#include "journal_reading.hpp"
#include "server/journal.hpp"
#include "server/journaled_device.hpp"
#include "support/small_tmpfs.hpp"
#include "support/temp_dir.hpp"

namespace mblab::server {
namespace {

using test::file_text;
using test::SmallTmpfs;
using test::TempDir;

std::vector<std::string> records_at(const std::filesystem::path& path) {
    auto read = read_all(path);
    EXPECT_TRUE(read.ok) << read.error;
    return read.records;
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

// A record of about 1 KiB, numbered: enough of them cross a page of the small tmpfs.
std::string big_record(int number) {
    return "1 T 10" + std::string(3000, 'A') + std::to_string(1000 + number);
}

// Attack run: a write cut short by a full disk left part of a record, the next record went on
// the same line, and after kill -9 serve refused to start. The failed append is cut off again,
// its writes are reported not written, and the records after it are whole.
TEST(Journal, AFailedAppendLeavesTheFileAsItWasAndTheNextRecordsWhole) {
    SmallTmpfs disk("64k");
    if (!disk.mounted()) GTEST_SKIP() << disk.why_not();
    const auto path = disk / "s.json.journal";
    auto journal = Journal::create(path);
    ASSERT_TRUE(journal) << journal.error();
    std::promise<bool> first;
    (*journal)->append(big_record(0), [&](bool written) { first.set_value(written); });
    ASSERT_TRUE(first.get_future().get());
    const auto good = std::filesystem::file_size(path);
    ASSERT_GT(disk.fill(), 0U);
    // Several records in one group: the first fits the page the file has, the rest do not.
    std::atomic<int> refused{0};
    std::promise<void> all_told;
    std::atomic<int> told{0};
    for (int i = 1; i <= 4; ++i) {
        (*journal)->append(big_record(i), [&](bool written) {
            if (!written) ++refused;
            if (++told == 4) all_told.set_value();
        });
    }
    all_told.get_future().wait();
    EXPECT_EQ(refused.load(), 4);
    EXPECT_EQ(std::filesystem::file_size(path), good);
    disk.free_space();
    std::promise<bool> after;
    (*journal)->append(big_record(5), [&](bool written) { after.set_value(written); });
    EXPECT_TRUE(after.get_future().get());
    journal.value().reset();
    const auto read = read_all(path);
    ASSERT_TRUE(read.ok) << read.error;
    EXPECT_EQ(read.records, (std::vector<std::string>{big_record(0), big_record(5)}));
    EXPECT_TRUE(read.warnings.empty());
}

// Attack run: with room for the journal but not for the state, the rotation appended the
// journal to PATH.old without checking the write, then truncated the journal: 712-715 of 800
// registers came back older. A rotation that fails moves and truncates nothing.
TEST(Journal, AFailedRotationKeepsEveryRecordWhereReplayFindsIt) {
    SmallTmpfs disk("64k");
    if (!disk.mounted()) GTEST_SKIP() << disk.why_not();
    const auto path = disk / "s.json.journal";
    auto journal = Journal::create(path);
    ASSERT_TRUE(journal) << journal.error();
    std::vector<std::string> expected;
    const auto add = [&](int number) {
        std::promise<bool> written;
        (*journal)->append(big_record(number), [&](bool ok) { written.set_value(ok); });
        const bool ok = written.get_future().get();
        if (ok) expected.push_back(big_record(number));
        return ok;
    };
    ASSERT_TRUE(add(0));
    (void)(*journal)->rotate();  // PATH.old now holds record 0; its save "fails": no drop_old
    for (int i = 1; i <= 8; ++i)
        ASSERT_TRUE(add(i));
    ASSERT_GT(disk.fill(), 0U);
    const auto second = (*journal)->rotate();  // must copy 16 KiB into PATH.old: no room
    EXPECT_FALSE(add(9));
    disk.free_space();
    ASSERT_TRUE(add(10));
    EXPECT_EQ(records_at(path), expected);
    // The save after it covers PATH.old's records only; PATH's stay.
    (*journal)->drop_old(second);
    ASSERT_TRUE(add(11));
    journal.value().reset();
    const auto left = records_at(path);
    ASSERT_FALSE(left.empty());
    EXPECT_EQ(left.back(), big_record(11));
    EXPECT_EQ(left.front(), big_record(1));
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
