#include <gtest/gtest.h>

#include <atomic>
#include <future>
#include <string>
#include <vector>

#include "server/state_saver.hpp"

namespace mblab::server {
namespace {

device::StateSnapshot snapshot_with(std::uint16_t value) {
    device::StateSnapshot snapshot;
    snapshot.profile = "test";
    snapshot.units.push_back({1, {{device::BankKind::HoldingRegisters, 0, {value}}}, {}});
    return snapshot;
}

// Issue 17 item 6: the save (JSON text, write, fsyncs) ran on the server's thread and stalled
// every client. Handing a snapshot over returns while the file is still being written.
TEST(StateSaver, SaveReturnsWhileTheFileIsStillBeingWritten) {
    std::promise<void> release;
    auto released = release.get_future().share();
    std::vector<std::string> written;
    StateSaver saver([&](const std::filesystem::path&, std::string_view text, std::string&) {
        released.wait();  // a disk that takes its time
        written.emplace_back(text);
        return true;
    });
    std::atomic<int> done{0};
    saver.save("a.json", snapshot_with(7), [&](bool saved, const std::string&) {
        EXPECT_TRUE(saved);
        ++done;
    });
    // Reaching this line is the point: save() did not wait for the write.
    EXPECT_EQ(done.load(), 0);
    release.set_value();
    saver.wait_idle();
    EXPECT_EQ(done.load(), 1);
    ASSERT_EQ(written.size(), 1U);
    EXPECT_NE(written[0].find("\"values\": [\n      7\n"), std::string::npos) << written[0];
}

TEST(StateSaver, ANewerSnapshotReplacesOneStillWaitingForTheSameFile) {
    std::promise<void> release;
    auto released = release.get_future().share();
    std::vector<std::string> paths;
    StateSaver saver([&](const std::filesystem::path& path, std::string_view, std::string&) {
        released.wait();
        paths.push_back(path.string());
        return true;
    });
    saver.save("a.json", snapshot_with(1), {});  // being written
    saver.save("b.json", snapshot_with(2), {});  // waits
    saver.save("b.json", snapshot_with(3), {});  // replaces the waiting one
    release.set_value();
    saver.wait_idle();
    EXPECT_EQ(paths, (std::vector<std::string>{"a.json", "b.json"}));
}

}  // namespace
}  // namespace mblab::server
