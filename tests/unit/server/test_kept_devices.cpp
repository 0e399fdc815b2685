// The devices `mblab serve` keeps: state files numbered per device, state restored and journals
// replayed at start, writes through the journal with --durable, every device saved at the end.
#include <gtest/gtest.h>

#include <array>
#include <filesystem>
#include <fstream>
#include <string>

#include "server/kept_devices.hpp"
#include "server/state_file.hpp"
#include "support/temp_dir.hpp"

namespace mblab::server {
namespace {

using test::TempDir;

// Unit 1 with holding registers 0-9.
constexpr std::string_view kProfile =
    "name = \"kept\"\nunit = [{ id = 1, holding_registers = [{ start = 0, count = 10 }] }]\n";

std::filesystem::path write_profile(const TempDir& dir) {
    const auto path = dir / "kept.toml";
    std::ofstream(path) << kProfile;
    return path;
}

std::size_t write_register(device::RequestHandler& handler, std::uint16_t address,
                           std::uint16_t value) {
    const std::array<std::uint8_t, 5> request{
        0x06, static_cast<std::uint8_t>(address >> 8), static_cast<std::uint8_t>(address),
        static_cast<std::uint8_t>(value >> 8), static_cast<std::uint8_t>(value)};
    std::array<std::uint8_t, 260> response{};
    return handler.handle({1, device::Link::Serial}, request, response).size;
}

TEST(KeptDevices, StateFilesAreNumberedFromOneWhenThereAreSeveral) {
    EXPECT_EQ(device_state_path("/d/lab.json", 0, 1), "/d/lab.json");
    EXPECT_EQ(device_state_path("/d/lab.json", 0, 3), "/d/lab-1.json");
    EXPECT_EQ(device_state_path("/d/lab.json", 2, 3), "/d/lab-3.json");
}

TEST(KeptDevices, WithoutStateNothingIsKept) {
    TempDir dir;
    auto kept = KeptDevices::open({write_profile(dir), 2, {}, false}, {});
    ASSERT_TRUE(kept) << kept.error();
    EXPECT_EQ((*kept)->size(), 2U);
    EXPECT_FALSE((*kept)->keeps_state());
    EXPECT_EQ((*kept)->keeper(0), nullptr);
    EXPECT_EQ(&(*kept)->handler(1), &(*kept)->device(1));
    EXPECT_TRUE((*kept)->save_all());
}

TEST(KeptDevices, WritesSurviveACloseAndAReopen) {
    TempDir dir;
    const KeptDevicesOptions options{write_profile(dir), 2, dir / "lab.json", false};
    {
        auto kept = KeptDevices::open(options, {});
        ASSERT_TRUE(kept) << kept.error();
        EXPECT_EQ(write_register((*kept)->handler(1), 4, 0xBEEF), 5U);
        EXPECT_TRUE((*kept)->save_all());
    }
    EXPECT_TRUE(std::filesystem::exists(dir / "lab-2.json"));
    auto kept = KeptDevices::open(options, {});
    ASSERT_TRUE(kept) << kept.error();
    EXPECT_EQ((*kept)->device(1).data().value(1, device::BankKind::HoldingRegisters, 4), 0xBEEF);
    EXPECT_EQ((*kept)->device(0).data().value(1, device::BankKind::HoldingRegisters, 4), 0);
}

TEST(KeptDevices, DurableWritesGoThroughTheJournalAndReplayWithoutASave) {
    TempDir dir;
    const KeptDevicesOptions options{write_profile(dir), 1, dir / "lab.json", true};
    {
        auto kept = KeptDevices::open(options, {});
        ASSERT_TRUE(kept) << kept.error();
        EXPECT_NE(&(*kept)->handler(0), &(*kept)->device(0));
        EXPECT_EQ(write_register((*kept)->handler(0), 7, 0x1234), 5U);
        EXPECT_GT(std::filesystem::file_size(journal_path_of(dir / "lab.json")), 0U);
        // No save_all: the journal alone must bring the write back.
    }
    auto kept = KeptDevices::open(options, {});
    ASSERT_TRUE(kept) << kept.error();
    EXPECT_EQ((*kept)->device(0).data().value(1, device::BankKind::HoldingRegisters, 7), 0x1234);
}

TEST(KeptDevices, ADamagedStateFileIsOneLineNamingTheFile) {
    TempDir dir;
    std::ofstream(dir / "lab.json") << "{not json";
    auto kept = KeptDevices::open({write_profile(dir), 1, dir / "lab.json", false}, {});
    ASSERT_FALSE(kept);
    EXPECT_NE(kept.error().find("lab.json"), std::string::npos) << kept.error();
    EXPECT_EQ(kept.error().find('\n'), std::string::npos) << kept.error();
}

TEST(KeptDevices, AProfileThatCannotBeLoadedIsRefused) {
    TempDir dir;
    auto kept = KeptDevices::open({dir / "missing.toml", 1, {}, false}, {});
    ASSERT_FALSE(kept);
    EXPECT_NE(kept.error().find("missing.toml"), std::string::npos) << kept.error();
}

}  // namespace
}  // namespace mblab::server
