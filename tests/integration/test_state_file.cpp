// The state file's save: atomic, and safe against links planted beside it.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "server/state_file.hpp"
#include "support/temp_dir.hpp"

namespace mblab::test {
namespace {

namespace fs = std::filesystem;

unsigned mode_of(const fs::path& path) {
    struct stat st {};
    ::stat(path.c_str(), &st);
    return st.st_mode & 07777;
}

// Issue 17 item 4: a symlink at FILE.tmp made the save overwrite the link's target.
TEST(StateFile, SaveDoesNotFollowALinkPlantedAtTheTemporaryName) {
    TempDir dir;
    auto victim = dir / "victim";
    std::ofstream(victim) << "precious\n";
    auto state = dir / "state.json";
    fs::create_symlink(victim, dir / "state.json.tmp");
    std::string error;
    ASSERT_TRUE(server::write_file_atomically(state, "{}\n", error)) << error;
    EXPECT_EQ(file_text(victim), "precious\n");
    EXPECT_EQ(file_text(state), "{}\n");
    EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(state)));
    std::size_t entries = 0;
    for ([[maybe_unused]] const auto& entry : fs::directory_iterator(dir.path()))
        ++entries;
    EXPECT_EQ(entries, 3U);  // victim, the planted link, the state: no temporary left
}

TEST(StateFile, NewFileIsPrivateAndAnExistingOneKeepsItsMode) {
    TempDir dir;
    auto state = dir / "state.json";
    std::string error;
    ASSERT_TRUE(server::write_file_atomically(state, "one\n", error)) << error;
    EXPECT_EQ(mode_of(state), 0600U);
    ASSERT_EQ(::chmod(state.c_str(), 0640), 0);
    ASSERT_TRUE(server::write_file_atomically(state, "two\n", error)) << error;
    EXPECT_EQ(mode_of(state), 0640U);
    EXPECT_EQ(file_text(state), "two\n");
}

TEST(StateFile, UnwritableDirectoryIsOneLine) {
    std::string error;
    EXPECT_FALSE(server::write_file_atomically("/nonexistent-dir/state.json", "{}", error));
    EXPECT_EQ(error,
              "cannot create a temporary file for /nonexistent-dir/state.json: No such file or "
              "directory");
}

}  // namespace
}  // namespace mblab::test
