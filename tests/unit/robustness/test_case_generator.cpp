#include <gtest/gtest.h>

#include <set>

#include "robustness/case_generator.hpp"
#include "robustness/line_cases.hpp"

namespace mblab::robustness {
namespace {

Recon reference_recon() {
    Recon recon;
    recon.served = {0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x08, 0x0F,
                    0x10, 0x14, 0x15, 0x16, 0x17, 0x18, 0x2B};
    return recon;
}

std::vector<FuzzCase> take(CaseGenerator& generator, std::size_t count) {
    std::vector<FuzzCase> out;
    for (std::size_t i = 0; i < count; ++i)
        out.push_back(generator.next());
    return out;
}

std::vector<std::uint8_t> all_bytes(const FuzzCase& c) {
    std::vector<std::uint8_t> out;
    for (const auto& step : c.steps)
        out.insert(out.end(), step.bytes.begin(), step.bytes.end());
    return out;
}

TEST(CaseGenerator, TheSameSeedGivesTheSameCases) {
    CaseGenerator a(reference_recon(), {}, 7);
    CaseGenerator b(reference_recon(), {}, 7);
    CaseGenerator c(reference_recon(), {}, 8);
    const std::size_t count = a.fixed_cases() + 50;
    const auto first = take(a, count);
    const auto second = take(b, count);
    const auto other = take(c, count);
    bool differs = false;
    for (std::size_t i = 0; i < count; ++i) {
        EXPECT_EQ(first[i].name, second[i].name);
        EXPECT_EQ(all_bytes(first[i]), all_bytes(second[i])) << first[i].name;
        differs = differs || all_bytes(first[i]) != all_bytes(other[i]);
    }
    // The seed drives the mutations.
    EXPECT_TRUE(differs);
}

// The fixed classes tried over `framing`.
std::set<BadInput> fixed_classes(protocol::Framing framing) {
    std::set<BadInput> out;
    for (std::size_t i = 0; i + 1 < kBadInputCount; ++i) {
        if (!not_applicable(static_cast<BadInput>(i), framing))
            out.insert(static_cast<BadInput>(i));
    }
    return out;
}

// A short budget reaches every class: one case of each comes before any class's second.
TEST(CaseGenerator, TheFirstRoundHasEveryFixedClass) {
    for (auto framing :
         {protocol::Framing::Mbap, protocol::Framing::Rtu, protocol::Framing::Ascii}) {
        CaseGenerator generator(reference_recon(), {true, std::nullopt}, 1, framing);
        const auto expected = fixed_classes(framing);
        std::set<BadInput> seen;
        for (const auto& c : take(generator, expected.size()))
            seen.insert(c.kind);
        EXPECT_EQ(seen, expected) << static_cast<int>(framing);
        EXPECT_EQ(take(generator, 1).front().kind, *expected.begin());
    }
}

TEST(CaseGenerator, TheFirstCasesAreTheKnownKillers) {
    CaseGenerator generator(reference_recon(), {true, std::nullopt}, 1);
    const auto cases = take(generator, kBadInputCount);
    EXPECT_EQ(cases[0].name, "protocol id 0x0001");
    EXPECT_EQ(all_bytes(cases[0]), (std::vector<std::uint8_t>{0x00, 0x01, 0x00, 0x01, 0x00, 0x06,
                                                              0x01, 0x03, 0x00, 0x00, 0x00, 0x01}));
    EXPECT_EQ(cases[1].name, "MBAP length 0 for 6 bytes");
    EXPECT_EQ(cases[5].name, "FC 0x10 byte count 0 for 1 registers, 2 data bytes");
    // After the transaction id: protocol 0, length 9, unit 1, FC 10 at 0, 1 register, count 0.
    const auto bytes = all_bytes(cases[5]);
    EXPECT_EQ(std::vector<std::uint8_t>(bytes.begin() + 2, bytes.end()),
              (std::vector<std::uint8_t>{0x00, 0x00, 0x00, 0x09, 0x01, 0x10, 0x00, 0x00, 0x00, 0x01,
                                         0x00, 0x00, 0x00}));
}

TEST(CaseGenerator, EveryCaseAfterTheFixedOnesIsAMutation) {
    CaseGenerator generator(reference_recon(), {}, 3);
    take(generator, generator.fixed_cases());
    for (const auto& c : take(generator, 200)) {
        EXPECT_EQ(c.kind, BadInput::Mutation);
        ASSERT_EQ(c.steps.size(), 1U);
        EXPECT_GE(c.steps[0].bytes.size(), 8U) << c.name;
    }
}

TEST(MaySend, ReadsAlwaysWritesOnlyInsideTheWritableRange) {
    const WritePolicy none{};
    const WritePolicy range{false, WritableRange{100, 10}};
    const WritePolicy all{true, std::nullopt};
    const std::vector<std::uint8_t> read = {0x03, 0xFF, 0xFF, 0x00, 0x7D};
    const std::vector<std::uint8_t> write_in = {0x10, 0x00, 0x64, 0x00, 0x0A, 0x14};
    const std::vector<std::uint8_t> write_past = {0x10, 0x00, 0x64, 0x00, 0x0B, 0x16};
    const std::vector<std::uint8_t> coil_out = {0x05, 0x00, 0x63, 0xFF, 0x00};
    const std::vector<std::uint8_t> listen_only = {0x08, 0x00, 0x04, 0x00, 0x00};
    EXPECT_TRUE(may_send(read, none));
    EXPECT_FALSE(may_send(write_in, none));
    EXPECT_TRUE(may_send(write_in, range));
    EXPECT_FALSE(may_send(write_past, range));
    EXPECT_FALSE(may_send(coil_out, range));
    EXPECT_FALSE(may_send(listen_only, range));
    EXPECT_TRUE(may_send(listen_only, all));
    EXPECT_TRUE(may_send(write_past, all));
}

// Without permission no case, fixed or mutated, carries a write outside the range.
TEST(CaseGenerator, NoCaseWritesOutsideThePolicy) {
    for (const WritePolicy& policy : {WritePolicy{}, WritePolicy{false, WritableRange{100, 10}}}) {
        CaseGenerator generator(reference_recon(), policy, 11);
        std::size_t withheld = 0;
        for (auto n : generator.withheld())
            withheld += n;
        EXPECT_GT(withheld, 0U);
        for (const auto& c : take(generator, generator.fixed_cases() + 2000)) {
            for (const auto& step : c.steps) {
                if (step.bytes.size() <= 7) continue;
                const std::span<const std::uint8_t> pdu(step.bytes.begin() + 7, step.bytes.end());
                // Pipelined frames hold reads only.
                EXPECT_TRUE(may_send(pdu, policy) || c.kind == BadInput::Pipelined ||
                            c.kind == BadInput::ManyConnections)
                    << c.name;
            }
        }
    }
}

}  // namespace
}  // namespace mblab::robustness
