// The journal's text as replay reads it: checksums, what an editor leaves (BOM, CRLF, blank
// lines), torn last records, and journals written before records had checksums.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "journal_reading.hpp"
#include "server/journal.hpp"
#include "server/journal_file.hpp"
#include "support/temp_dir.hpp"

namespace mblab::server {
namespace {

using test::file_text;
using test::TempDir;

void write_text(const std::filesystem::path& path, const std::string& text) {
    std::ofstream(path, std::ios::binary) << text;
}

// Three records written by the journal itself, as the file holds them.
std::string journal_of_three(const std::filesystem::path& path) {
    {
        auto journal = Journal::create(path);
        EXPECT_TRUE(journal) << journal.error();
        for (const char* record : {"1 T 0600010001", "1 T 0600020002", "1 T 0600030003"})
            (*journal)->append(record, {});
    }
    return file_text(path);
}

TEST(JournalFile, Crc32IsTheUsualOne) {
    EXPECT_EQ(crc32_of("123456789"), 0xCBF43926U);
    EXPECT_EQ(seal_record("123456789"), "123456789*CBF43926");
}

TEST(JournalFile, EveryRecordIsSealedWithItsChecksum) {
    TempDir dir;
    const auto text = journal_of_three(dir / "j");
    EXPECT_EQ(text, seal_record("1 T 0600010001") + "\n" + seal_record("1 T 0600020002") + "\n" +
                        seal_record("1 T 0600030003") + "\n");
}

// Attack run: one changed hex digit replayed a wrong value without a word.
TEST(JournalFile, AChangedDigitIsRefusedNamingTheFileTheLineAndWhatToDo) {
    TempDir dir;
    auto text = journal_of_three(dir / "j");
    text[text.find("0002")] = '9';
    write_text(dir / "j", text);
    const auto read = read_all(dir / "j");
    EXPECT_FALSE(read.ok);
    EXPECT_EQ(read.error, "journal " + (dir / "j").string() +
                              " line 2: its checksum does not match (the line was changed or cut "
                              "short); restore the line, or delete it (its write is then lost) "
                              "and start again");
}

// Never acknowledged: its fdatasync had not returned when the crash cut it.
TEST(JournalFile, ABadOrTornLastRecordIsLeftOutWithAWarning) {
    TempDir dir;
    const auto text = journal_of_three(dir / "j");
    write_text(dir / "j", text.substr(0, text.size() - 5));
    auto read = read_all(dir / "j");
    ASSERT_TRUE(read.ok) << read.error;
    EXPECT_EQ(read.records, (std::vector<std::string>{"1 T 0600010001", "1 T 0600020002"}));
    ASSERT_EQ(read.warnings.size(), 1U);
    EXPECT_NE(read.warnings[0].find("line 3: left out"), std::string::npos) << read.warnings[0];

    auto changed = text;
    changed[changed.rfind("0003")] = '7';
    write_text(dir / "j", changed + "\n\n");
    read = read_all(dir / "j");
    ASSERT_TRUE(read.ok) << read.error;
    EXPECT_EQ(read.records.size(), 2U);
    EXPECT_EQ(read.warnings.size(), 1U);
}

// Attack run: a line an editor changed (BOM, CRLF, a blank line) stopped the start with no hint.
TEST(JournalFile, ABomCrlfLineEndsAndBlankLinesAreTaken) {
    TempDir dir;
    auto text = journal_of_three(dir / "j");
    std::string edited = "\xEF\xBB\xBF";
    for (std::size_t begin = 0, end; (end = text.find('\n', begin)) != std::string::npos;
         begin = end + 1) {
        edited += text.substr(begin, end - begin) + "\r\n\r\n  \n";
    }
    write_text(dir / "j", edited);
    const auto read = read_all(dir / "j");
    ASSERT_TRUE(read.ok) << read.error;
    EXPECT_EQ(read.records,
              (std::vector<std::string>{"1 T 0600010001", "1 T 0600020002", "1 T 0600030003"}));
    EXPECT_EQ(read.lines, (std::vector<std::size_t>{1, 4, 7}));
    EXPECT_TRUE(read.warnings.empty());
}

// An editor that drops the last newline leaves a whole record: its checksum says so.
TEST(JournalFile, ALastRecordWithoutItsNewlineButWholeIsKept) {
    TempDir dir;
    const auto text = journal_of_three(dir / "j");
    write_text(dir / "j", text.substr(0, text.size() - 1));
    const auto read = read_all(dir / "j");
    ASSERT_TRUE(read.ok) << read.error;
    EXPECT_EQ(read.records.size(), 3U);
    EXPECT_TRUE(read.warnings.empty());
}

TEST(JournalFile, JournalsFromBeforeChecksumsAreReadButNotMixedIn) {
    TempDir dir;
    write_text(dir / "j", "1 T 0600010001\n1 T 0600020002\n");
    auto read = read_all(dir / "j");
    ASSERT_TRUE(read.ok) << read.error;
    EXPECT_EQ(read.records, (std::vector<std::string>{"1 T 0600010001", "1 T 0600020002"}));

    // Once a file has checksums, a record without one is a damaged record, not an old one.
    write_text(dir / "j", seal_record("1 T 0600010001") + "\n1 T 0600020002\n" +
                              seal_record("1 T 0600030003") + "\n");
    read = read_all(dir / "j");
    EXPECT_FALSE(read.ok);
    EXPECT_NE(read.error.find("line 2: it has no checksum"), std::string::npos) << read.error;
}

TEST(JournalFile, TheOldFileIsReadFirst) {
    TempDir dir;
    write_text(dir / "j.old", seal_record("1 T 0600010001") + "\n");
    write_text(dir / "j", seal_record("1 T 0600020002") + "\n");
    EXPECT_EQ(read_all(dir / "j").records,
              (std::vector<std::string>{"1 T 0600010001", "1 T 0600020002"}));
}

}  // namespace
}  // namespace mblab::server
