#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>
#include <string>

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

namespace mblab::robustness {
namespace {

// The pairwise cases of a run, in the order they come.
std::vector<FuzzCase> pairwise_cases(const Recon& recon, const WritePolicy& policy,
                                     protocol::Framing framing = protocol::Framing::Mbap,
                                     std::uint64_t seed = 1) {
    CaseGenerator generator(recon, policy, seed, framing);
    std::vector<FuzzCase> out;
    for (auto& c : take(generator, generator.fixed_cases())) {
        if (c.kind == BadInput::Pairwise) out.push_back(std::move(c));
    }
    return out;
}

std::set<std::uint8_t> functions_of(const std::vector<FuzzCase>& cases) {
    std::set<std::uint8_t> out;
    for (const auto& c : cases) {
        const auto bytes = all_bytes(c);
        out.insert(bytes.at(7));
    }
    return out;
}

std::size_t withheld_pairwise(const CaseGenerator& generator) {
    const auto& withheld = generator.withheld();
    const auto at = static_cast<std::size_t>(BadInput::Pairwise);
    return at < withheld.size() ? withheld[at] : 0;
}

// Served or not: a device may parse a request before it finds it does not serve it.
TEST(CaseGeneratorPairwise, EveryFunctionWithALayoutServedOrNot) {
    const WritePolicy all{true, std::nullopt};
    const std::set<std::uint8_t> laid_out{0x01, 0x02, 0x03, 0x04, 0x05, 0x06,
                                          0x08, 0x0F, 0x10, 0x16, 0x17, 0x2B};
    EXPECT_EQ(functions_of(pairwise_cases(reference_recon(), all)), laid_out);
    Recon two;
    two.served = {0x03, 0x10};
    EXPECT_EQ(functions_of(pairwise_cases(two, all)), laid_out);
}

// A device that serves FC 03 alone: the malformed requests of every other public code are made
// all the same, and a write among them only where writes are allowed.
TEST(CaseGenerator, MalformedRequestsCoverCodesTheDeviceDoesNotServe) {
    Recon recon;
    recon.served = {0x03};
    recon.not_served = {0x01, 0x02, 0x04, 0x05, 0x06, 0x0F, 0x10, 0x17};
    CaseGenerator allowed(recon, {true, std::nullopt}, 1);
    std::map<std::string, std::vector<std::uint8_t>> pdu_of;
    for (const auto& c : take(allowed, allowed.fixed_cases())) {
        const auto bytes = all_bytes(c);
        if (c.steps.size() == 1 && bytes.size() > 7)
            pdu_of[c.name] = std::vector<std::uint8_t>(bytes.begin() + 7, bytes.end());
    }
    // FC 17 with a write quantity over 121 and of 0 (the read and write quantities at 0x03, 0x07).
    ASSERT_TRUE(pdu_of.count("FC 0x17 write quantity 122"));
    EXPECT_EQ(pdu_of["FC 0x17 write quantity 122"][0], 0x17);
    EXPECT_EQ(pdu_of["FC 0x17 write quantity 122"][8], 122);
    EXPECT_TRUE(pdu_of.count("FC 0x17 read quantity 0"));
    EXPECT_TRUE(pdu_of.count("FC 0x17 byte count 0 for 1 written registers"));
    EXPECT_TRUE(std::any_of(pdu_of.begin(), pdu_of.end(), [](const auto& named) {
        const auto& pdu = named.second;
        return named.first.starts_with("FC 0x17 unit") && pdu.size() >= 9 && pdu[7] == 0 &&
               pdu[8] == 0;
    })) << "no pairwise FC 17 row with a write quantity of 0";
    for (const char* name : {"FC 0x17 alone", "FC 0x17 cut to 2 bytes", "FC 0x01 quantity 0",
                             "FC 0x04 quantity 126", "FC 0x10 quantity 124", "FC 0x0F quantity 0"})
        EXPECT_TRUE(pdu_of.count(name)) << name;

    // Without permission the reads are still made, the writes withheld and counted.
    CaseGenerator none(recon, {}, 1);
    std::set<std::string> names;
    for (const auto& c : take(none, none.fixed_cases()))
        names.insert(c.name);
    EXPECT_TRUE(names.count("FC 0x04 quantity 126"));
    EXPECT_FALSE(names.count("FC 0x17 write quantity 122"));
    EXPECT_GT(none.withheld()[static_cast<std::size_t>(BadInput::Quantity)], 0U);
}

// A function at a time in turn: the first pairwise cases reach every function, each with its
// nominal request (a right header, fields in range).
TEST(CaseGeneratorPairwise, TheFirstRowOfEachFunctionComesFirstAndIsNominal) {
    const auto cases = pairwise_cases(reference_recon(), {true, std::nullopt});
    ASSERT_GE(cases.size(), 12U);
    const std::vector<FuzzCase> first(cases.begin(), cases.begin() + 12);
    EXPECT_EQ(functions_of(first).size(), 12U);
    EXPECT_EQ(first[2].name, "FC 0x03 unit 1 address 0x0000 quantity 1 length right");
    const auto bytes = all_bytes(first[2]);
    EXPECT_EQ(
        std::vector<std::uint8_t>(bytes.begin() + 2, bytes.end()),
        (std::vector<std::uint8_t>{0x00, 0x00, 0x00, 0x06, 0x01, 0x03, 0x00, 0x00, 0x00, 0x01}));
}

TEST(CaseGeneratorPairwise, WritesOutsideThePolicyAreWithheldAndCounted) {
    const auto recon = reference_recon();
    for (const WritePolicy& policy : {WritePolicy{}, WritePolicy{false, WritableRange{100, 10}}}) {
        CaseGenerator generator(recon, policy, 1);
        const auto sent = pairwise_cases(recon, policy);
        // The same rows with writes allowed (the range decides the write addresses): those
        // withheld are left out and counted.
        const auto every = pairwise_cases(recon, {true, policy.writable});
        EXPECT_GT(withheld_pairwise(generator), 0U);
        EXPECT_EQ(sent.size() + withheld_pairwise(generator), every.size());
        std::set<std::uint8_t> functions;
        for (const auto& c : sent) {
            const auto bytes = all_bytes(c);
            const std::span<const std::uint8_t> pdu(bytes.begin() + 7, bytes.end());
            EXPECT_TRUE(may_send(pdu, policy)) << c.name;
            EXPECT_EQ(c.name.find("sub-function 0x0001"), std::string::npos) << c.name;
            functions.insert(pdu[0]);
        }
        EXPECT_TRUE(functions.count(0x08));
        for (std::uint8_t write : {0x05, 0x06, 0x0F, 0x10, 0x16, 0x17}) {
            // Read-only: no write at all; inside the range, the rows aimed inside it.
            EXPECT_EQ(functions.count(write), policy.writable ? 1U : 0U) << int(write);
        }
    }
}

TEST(CaseGeneratorPairwise, TheSameForTheSameSeed) {
    const auto a = pairwise_cases(reference_recon(), {}, protocol::Framing::Mbap, 5);
    const auto b = pairwise_cases(reference_recon(), {}, protocol::Framing::Mbap, 5);
    ASSERT_EQ(a.size(), b.size());
    ASSERT_FALSE(a.empty());
    for (std::size_t i = 0; i < a.size(); ++i) {
        EXPECT_EQ(a[i].name, b[i].name);
        EXPECT_EQ(all_bytes(a[i]), all_bytes(b[i])) << a[i].name;
    }
}

// The FC 03 frames decoded: every value of every field meets every value of every other field
// in some frame, MBAP fields included. The transaction id is 0, 0xFFFF or the generator's own
// count (-1 here).
TEST(CaseGeneratorPairwise, EveryPairOfFc03FieldValuesIsInSomeFrame) {
    Recon recon = reference_recon();
    recon.unit = 5;
    recon.check_address = 100;
    recon.max_read = 60;
    std::vector<std::array<long, 6>> frames;
    for (const auto& c : pairwise_cases(recon, {})) {
        const auto b = all_bytes(c);
        if (b.at(7) != 0x03) continue;
        ASSERT_EQ(b.size(), 12U) << c.name;
        const long transaction = b[0] << 8 | b[1];
        frames.push_back({transaction == 0 || transaction == 0xFFFF ? transaction : -1,
                          b[2] << 8 | b[3], b[4] << 8 | b[5], b[6], b[8] << 8 | b[9],
                          b[10] << 8 | b[11]});
    }
    const std::array<std::set<long>, 6> expected = {
        {{-1, 0, 0xFFFF},                                 // transaction
         {0, 1},                                          // protocol
         {6, 0, 1, 5, 7, 255},                            // length: right, 0, 1, right -+ 1, 255
         {5, 0, 255, 247, 1},                             // unit
         {100, 0, 1, 0x7FFF, 0xFFFE, 0xFFFF},             // address
         {1, 0, 60, 125, 126, 0x7FFF, 0xFFFE, 0xFFFF}}};  // quantity
    std::array<std::set<long>, 6> seen;
    std::set<std::tuple<std::size_t, long, std::size_t, long>> pairs;
    for (const auto& f : frames) {
        for (std::size_t i = 0; i < 6; ++i) {
            seen[i].insert(f[i]);
            for (std::size_t j = i + 1; j < 6; ++j)
                pairs.insert({i, f[i], j, f[j]});
        }
    }
    EXPECT_EQ(seen, expected);
    for (std::size_t i = 0; i < 6; ++i) {
        for (std::size_t j = i + 1; j < 6; ++j) {
            for (long a : expected[i]) {
                for (long b : expected[j])
                    EXPECT_TRUE(pairs.count({i, a, j, b}))
                        << "fields " << i << ", " << j << ": " << a << ", " << b;
            }
        }
    }
    // Far fewer than every combination (3 * 2 * 6 * 5 * 6 * 8 = 8640).
    EXPECT_LE(frames.size(), 60U);
    EXPECT_GE(frames.size(), 48U);
}

// On a line the MBAP fields are no parameters: every pairwise frame re-frames whole, to the
// device's address or broadcast, and there are fewer rows.
TEST(CaseGeneratorPairwise, OnALineWithoutTheMbapFields) {
    const auto tcp = pairwise_cases(reference_recon(), {});
    for (auto framing : {protocol::Framing::Rtu, protocol::Framing::Ascii}) {
        const auto line = pairwise_cases(reference_recon(), {}, framing);
        ASSERT_FALSE(line.empty());
        EXPECT_LT(line.size(), tcp.size());
        for (const auto& c : line) {
            EXPECT_EQ(c.name.find("length"), std::string::npos) << c.name;
            EXPECT_EQ(c.name.find("transaction"), std::string::npos) << c.name;
            ASSERT_EQ(c.steps.size(), 1U);
            if (framing == protocol::Framing::Rtu) {
                const auto address = c.steps[0].bytes.at(0);
                EXPECT_TRUE(address == 1 || address == 0) << c.name;
            }
        }
    }
}

}  // namespace
}  // namespace mblab::robustness
