#include <gtest/gtest.h>

#include "robustness/recon.hpp"

namespace mblab::robustness {
namespace {

// A fake device: holding registers 100..149 only, FC 03 and 06 served, units 1 and 255.
std::optional<std::vector<std::uint8_t>> fake(std::uint8_t unit,
                                              std::span<const std::uint8_t> pdu) {
    if (unit != 1 && unit != 255) return std::nullopt;
    const std::uint8_t function = pdu[0];
    if (function == 0x06) return std::vector<std::uint8_t>{0x86, 0x03};
    if (function != 0x03)
        return std::vector<std::uint8_t>{static_cast<std::uint8_t>(function | 0x80), 0x01};
    const unsigned address = pdu[1] << 8 | pdu[2];
    const unsigned quantity = pdu[3] << 8 | pdu[4];
    if (address < 100 || address + quantity > 150) return std::vector<std::uint8_t>{0x83, 0x02};
    std::vector<std::uint8_t> answer = {0x03, static_cast<std::uint8_t>(2 * quantity)};
    answer.resize(2 + 2 * quantity, 0);
    return answer;
}

TEST(Recon, LearnsWhatTheDeviceServes) {
    Recon recon;
    ASSERT_FALSE(reconnoitre(fake, {}, recon));
    EXPECT_EQ(recon.served, (std::vector<std::uint8_t>{0x03, 0x06}));
    EXPECT_EQ(recon.check_address, 100);
    EXPECT_EQ(recon.max_read, 50);
    EXPECT_FALSE(recon.answers_unit_0);
    EXPECT_TRUE(recon.answers_unit_255);
    // The reads answered while probing: the binary search reached 100..149.
    EXPECT_EQ(recon.ranges.of(Table::HoldingRegisters), (std::vector<AddressRange>{{100, 149}}));
    EXPECT_TRUE(recon.ranges.of(Table::Coils).empty());
}

TEST(Recon, ProbesWritesWithRequestsThatChangeNothing) {
    EXPECT_EQ(*probe_request(0x06, false), (std::vector<std::uint8_t>{0x06, 0x00, 0x00}));
    EXPECT_EQ(*probe_request(0x05, false),
              (std::vector<std::uint8_t>{0x05, 0x00, 0x00, 0x12, 0x34}));
    EXPECT_EQ(probe_request(0x06, true)->size(), 5U);
}

TEST(Recon, NoReadableRegisterIsOneLine) {
    Recon recon;
    const auto failed = reconnoitre(
        [](std::uint8_t, std::span<const std::uint8_t>) {
            return std::optional(std::vector<std::uint8_t>{0x83, 0x02});
        },
        {}, recon);
    ASSERT_TRUE(failed);
    EXPECT_EQ(*failed,
              "no holding register at 0, 1, 100, 1000 or 40000 answers FC 03 with unit 1: the "
              "liveness check needs one (try --unit)");
}

// The device answered the read before the FC 10 probe and never after it: the probe killed it.
TEST(Recon, AProbeAfterWhichTheReadGoesUnansweredIsLeftAsTheKiller) {
    bool dead = false;
    const Ask dies_on_fc10 = [&](std::uint8_t unit, std::span<const std::uint8_t> pdu) {
        if (dead) return std::optional<std::vector<std::uint8_t>>{};
        if (pdu[0] == 0x10) dead = true;
        return fake(unit, pdu);
    };
    Recon recon;
    ASSERT_FALSE(reconnoitre(dies_on_fc10, {}, recon));
    ASSERT_TRUE(recon.killed_by);
    EXPECT_EQ(recon.killed_by->function, 0x10);
    EXPECT_EQ(recon.killed_by->request, *probe_request(0x10, false));
    EXPECT_EQ(recon.check_address, 100);
    // The probes before it were judged as usual.
    EXPECT_EQ(recon.served, (std::vector<std::uint8_t>{0x03, 0x06}));

    // A device that answers nothing from the start is the usage error it always was.
    Recon silent;
    EXPECT_TRUE(reconnoitre(
        [](std::uint8_t, std::span<const std::uint8_t>) {
            return std::optional<std::vector<std::uint8_t>>{};
        },
        {}, silent));
    EXPECT_FALSE(silent.killed_by);
}

}  // namespace
}  // namespace mblab::robustness
