// serve's keeper of a device's state: the journal's bound, REST writes in the journal in the
// order the device made them, and replay.
#include <gtest/gtest.h>

#include <array>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "device/reference_device.hpp"
#include "server/journaled_device.hpp"
#include "server/state_file.hpp"
#include "server/state_keeper.hpp"
#include "support/device_profiles.hpp"
#include "support/temp_dir.hpp"

namespace mblab::server {
namespace {

using test::TempDir;

constexpr std::string_view kProfile = R"(
name = "keeper"
[[unit]]
id = 1
coils = [{start = 0, count = 16}]
holding_registers = [{start = 0, count = 100}]
)";

std::unique_ptr<device::ReferenceDevice> make_device() {
    return test::device_from(kProfile);
}

// FC 06 through the journaled device, as a serial line makes it (waiting for the sync).
bool write_register(JournaledDevice& journaled, std::uint16_t address, std::uint16_t value) {
    const std::array<std::uint8_t, 5> request{
        0x06, static_cast<std::uint8_t>(address >> 8), static_cast<std::uint8_t>(address),
        static_cast<std::uint8_t>(value >> 8), static_cast<std::uint8_t>(value)};
    std::array<std::uint8_t, 260> response{};
    const auto reply = journaled.handle({1, device::Link::Serial}, request, response);
    return reply.size == 5 && response[0] == 0x06;
}

std::uint64_t journal_bytes(const std::filesystem::path& state) {
    std::uint64_t total = 0;
    for (const auto& file : {journal_path_of(state), journal_old_path(journal_path_of(state))}) {
        std::error_code ec;
        const auto size = std::filesystem::file_size(file, ec);
        if (!ec) total += size;
    }
    return total;
}

std::unique_ptr<StateKeeper> durable_keeper(device::ReferenceDevice& device,
                                            const std::filesystem::path& state, StateSaver& saver,
                                            std::uint64_t bound = kJournalBound) {
    auto journal = Journal::create(journal_path_of(state));
    EXPECT_TRUE(journal) << journal.error();
    return std::make_unique<StateKeeper>(device, state, saver, std::move(journal.value()),
                                         StateKeeper::Report{}, bound);
}

std::unique_ptr<device::ReferenceDevice> restarted(const std::filesystem::path& state) {
    auto device = make_device();
    std::string error;
    if (auto text = read_state_file(state, error)) {
        EXPECT_TRUE(device->state().load(*text, error)) << error;
    }
    EXPECT_TRUE(replay_journal(*device, state, {}, error)) << error;
    return device;
}

// Attack run: with --save-interval 0 the journal grew without bound (2.5 GB an hour). Past its
// bound a save compacts it, with no periodic save at all.
TEST(StateKeeper, TheJournalIsCompactedPastItsBoundWithoutPeriodicSaves) {
    TempDir dir;
    const auto state = dir / "s.json";
    auto device = make_device();
    constexpr std::uint64_t kBound = 2000;
    {
        StateSaver saver;
        auto keeper = durable_keeper(*device, state, saver, kBound);
        JournaledDevice journaled(*keeper);
        for (int i = 0; i < 2000; ++i)
            ASSERT_TRUE(write_register(journaled, static_cast<std::uint16_t>(i % 100),
                                       static_cast<std::uint16_t>(i)));
        saver.wait_idle();
        // 2000 records are about 54 KB; what is left is at most a bound before the last save,
        // one after it, and what came while that save ran.
        EXPECT_TRUE(std::filesystem::exists(state));
    }
    EXPECT_LT(journal_bytes(state), 3 * kBound + 1000);
    auto again = restarted(state);
    for (std::uint16_t address = 0; address < 100; ++address)
        EXPECT_EQ(again->data().value(1, device::BankKind::HoldingRegisters, address),
                  1900 + address);
}

// Attack run: REST writes were not journaled (50 of 50 lost on kill -9), and an older Modbus
// write was replayed over them.
TEST(StateKeeper, RestWritesAreJournaledInTheOrderTheDeviceMadeThem) {
    TempDir dir;
    const auto state = dir / "s.json";
    auto device = make_device();
    {
        StateSaver saver;
        auto keeper = durable_keeper(*device, state, saver);
        JournaledDevice journaled(*keeper);
        ASSERT_TRUE(write_register(journaled, 5, 1));
        const std::vector<std::uint16_t> values{2, 3};
        EXPECT_EQ(keeper->write_values(1, device::BankKind::HoldingRegisters, 5, values),
                  StateKeeper::Write::Done);
        const std::vector<std::uint16_t> coils{1, 0, 1};
        EXPECT_EQ(keeper->write_values(1, device::BankKind::Coils, 2, coils),
                  StateKeeper::Write::Done);
        ASSERT_TRUE(write_register(journaled, 7, 4));
        EXPECT_EQ(keeper->write_values(1, device::BankKind::HoldingRegisters, 99, values),
                  StateKeeper::Write::Unmapped);
        // No save: as after kill -9, only the journal has them.
    }
    EXPECT_FALSE(std::filesystem::exists(state));
    auto again = restarted(state);
    EXPECT_EQ(again->data().value(1, device::BankKind::HoldingRegisters, 5), 2);
    EXPECT_EQ(again->data().value(1, device::BankKind::HoldingRegisters, 6), 3);
    EXPECT_EQ(again->data().value(1, device::BankKind::HoldingRegisters, 7), 4);
    EXPECT_EQ(again->data().value(1, device::BankKind::Coils, 2), 1);
    EXPECT_EQ(again->data().value(1, device::BankKind::Coils, 3), 0);
    EXPECT_EQ(again->data().value(1, device::BankKind::Coils, 4), 1);
    EXPECT_FALSE(std::filesystem::exists(journal_path_of(state)));
}

TEST(JournalRecord, ValuesRecordsRoundTripThroughReplay) {
    const std::vector<std::uint16_t> values{0x1234, 0xABCD};
    EXPECT_EQ(values_record(9, device::BankKind::HoldingRegisters, 0x10, values),
              "9 V H 0010 1234ABCD");
    EXPECT_EQ(values_record(1, device::BankKind::Coils, 3, std::vector<std::uint16_t>{1}),
              "1 V C 0003 0001");
    auto device = make_device();
    EXPECT_TRUE(replay_record(*device, "1 V H 0010 1234ABCD"));
    EXPECT_EQ(device->data().value(1, device::BankKind::HoldingRegisters, 0x11), 0xABCD);
    EXPECT_TRUE(replay_record(*device, "1 V H 0020 00FF"));
    EXPECT_EQ(device->data().value(1, device::BankKind::HoldingRegisters, 0x20), 0xFF);
    for (const char* bad : {"1 V H 0010", "1 V X 0010 0001", "1 V H 0010 123", "1 V H 00G0 0001",
                            "1 V H 0010 0001 ", "1 W H 0010 0001"}) {
        EXPECT_FALSE(replay_record(*device, bad)) << bad;
    }
}

}  // namespace
}  // namespace mblab::server
