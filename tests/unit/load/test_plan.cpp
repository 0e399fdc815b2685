#include <gtest/gtest.h>

#include "conformance/catalogue.hpp"
#include "load/plan.hpp"
#include "support/hex.hpp"

namespace mblab::load {
namespace {

using std::chrono::milliseconds;
using test::hex;

conformance::Suite policy() {
    auto suite =
        conformance::load_suite_file(std::string(MBLAB_SOURCE_DIR) + "/catalogue/policy-2.1.toml");
    EXPECT_TRUE(suite.ok()) << suite.error();
    return suite.value();
}

std::vector<std::string> ids(const LoadPlan& plan) {
    std::vector<std::string> out;
    for (const auto& c : plan.cases)
        out.push_back(c.id);
    return out;
}

TEST(LoadPlan, PolicyRequestResponseCasesLoop) {
    LoadPlan plan;
    conformance::Dut dut;
    dut.unit = 1;
    dut.registers = 65536;
    ASSERT_TRUE(add_protocol_tests(plan, {policy()}, dut, {}).ok());
    EXPECT_EQ(ids(plan), (std::vector<std::string>{"7.3.1", "7.4.1", "7.5.1", "7.6.1", "7.7.1",
                                                   "7.8.1", "7.9.1", "7.10.1", "7.11.1", "7.12.1",
                                                   "9.1.1", "9.1.2", "9.1.4"}));
    // The four write cases read back what they wrote: four steps each.
    EXPECT_EQ(plan.test_exchanges, 25U);
    std::vector<std::pair<std::string, std::string>> left;
    for (const auto& item : plan.left_out)
        left.emplace_back(item.id, item.reason);
    EXPECT_EQ(left, (std::vector<std::pair<std::string, std::string>>{
                        {"7.2", "procedure ping"},
                        {"7.5.2", "procedure register_sweep"},
                        {"7.13.1", "N/A: the DUT does not declare object_messaging"},
                        {"7.13.2", "N/A: the DUT does not declare alternate_encoding"},
                        {"9.1.3", "needs a connection of its own"}}));
    const LoadExchange& read = plan.exchanges[2];
    EXPECT_EQ(read.name, "7.5.1");
    EXPECT_EQ(read.source, "CTP 7.5.1");
    EXPECT_EQ(read.request, hex("00 00 00 00 00 06 01 03 00 00 00 01"));
    ASSERT_EQ(read.answers.size(), 1U);
    EXPECT_TRUE(read.answers[0].matches(hex("AB CD 00 00 00 05 01 03 02 00 00")));
    EXPECT_EQ(plan.exchanges[5].name, "7.7.1 step 2");
    EXPECT_EQ(plan.exchanges[5].request, hex("00 00 00 00 00 06 01 01 00 00 00 01"));
    EXPECT_TRUE(plan.exchanges[5].answers[0].matches(hex("00 07 00 00 00 04 01 01 01 01")));
    EXPECT_FALSE(plan.exchanges[5].answers[0].matches(hex("00 07 00 00 00 04 01 01 01 00")));
    // 9.1.2 reads past the declared registers: all 65536 are there, so two from 0xFFFF.
    EXPECT_EQ(plan.exchanges[23].name, "9.1.2");
    EXPECT_EQ(plan.exchanges[23].request, hex("00 00 00 00 00 06 01 03 FF FF 00 02"));
    // 9.1.4 accepts 02 as well as 03.
    EXPECT_EQ(plan.exchanges[24].answers.size(), 2U);
}

TEST(LoadPlan, OutOfRangeWithoutADeclaredCountIsTwoExchanges) {
    LoadPlan plan;
    conformance::Dut dut;
    ASSERT_TRUE(add_protocol_tests(plan, {policy()}, dut, {"9.1.2"}).ok());
    ASSERT_EQ(plan.test_exchanges, 2U);
    // 0x8001 may answer 02 or data; the read past the end must answer 02.
    EXPECT_EQ(plan.exchanges[0].request, hex("00 00 00 00 00 06 01 03 80 01 00 01"));
    EXPECT_TRUE(plan.exchanges[0].answers[0].matches(hex("00 05 00 00 00 03 01 83 02")));
    EXPECT_TRUE(plan.exchanges[0].answers[1].matches(hex("00 05 00 00 00 05 01 03 02 12 34")));
    EXPECT_EQ(plan.exchanges[1].request, hex("00 00 00 00 00 06 01 03 FF FF 00 02"));
    ASSERT_EQ(plan.exchanges[1].answers.size(), 1U);
    EXPECT_FALSE(
        plan.exchanges[1].answers[0].matches(hex("00 05 00 00 00 07 01 03 04 00 00 00 00")));
}

TEST(LoadPlan, ReadBacksOfRangesTheMixWritesKeepTheirFormOnly) {
    LoadPlan plan;
    conformance::Dut dut;
    ASSERT_TRUE(add_protocol_tests(plan, {policy()}, dut, {"7.7.1", "7.8.1"}).ok());
    add_mix(plan, parse_mix("fc16:10=1").value(), dut);  // registers 0x10..0x19
    EXPECT_EQ(plan.values_unchecked, (std::vector<std::string>{"7.8.1 step 2", "7.8.1 step 4"}));
    const LoadExchange& register_read = plan.exchanges[5];
    EXPECT_TRUE(register_read.answers[0].matches(hex("00 01 00 00 00 05 01 03 02 12 34")));
    EXPECT_TRUE(register_read.answers[0].matches(hex("00 01 00 00 00 05 01 03 02 AA BB")));
    EXPECT_FALSE(register_read.answers[0].matches(hex("00 01 00 00 00 05 01 03 03 AA BB")));
    // No coil is written by the mix: the coil read-back still pins its value.
    EXPECT_FALSE(plan.exchanges[1].answers[0].matches(hex("00 01 00 00 00 04 01 01 01 00")));
}

TEST(LoadPlan, CaseChoiceAndMultiStepCases) {
    LoadPlan plan;
    auto suite = conformance::load_suite_file(std::string(MBLAB_SOURCE_DIR) +
                                              "/catalogue/function-codes.toml");
    ASSERT_TRUE(suite.ok()) << suite.error();
    conformance::Dut dut;
    dut.registers = 65536;
    ASSERT_TRUE(add_protocol_tests(plan, {policy(), suite.value()}, dut, {"7.8.1", "fc01.1"}).ok());
    EXPECT_EQ(ids(plan), (std::vector<std::string>{"7.8.1", "fc01.1"}));
    EXPECT_TRUE(plan.cases[1].unsupported_is_na);
    EXPECT_TRUE(plan.exchanges[0].first_step);
    EXPECT_FALSE(plan.exchanges[1].first_step);
    EXPECT_EQ(plan.exchanges[3].test_case, 0U);
    EXPECT_TRUE(plan.exchanges[4].first_step);
    EXPECT_EQ(plan.exchanges[4].test_case, 1U);

    LoadPlan missing;
    auto error = add_protocol_tests(missing, {policy()}, dut, {"7.99"});
    ASSERT_FALSE(error.ok());
    EXPECT_EQ(error.error(), "no case 7.99 in the chosen suites");
}

TEST(LoadPlan, MixFollowsTheTests) {
    LoadPlan plan;
    conformance::Dut dut;
    ASSERT_TRUE(add_protocol_tests(plan, {policy()}, dut, {"7.3.1"}).ok());
    add_mix(plan, parse_mix("fc3:2=3,fc6=1").value(), dut);
    ASSERT_EQ(plan.exchanges.size(), 3U);
    EXPECT_EQ(plan.exchanges[1].name, "fc3:2");
    EXPECT_EQ(plan.exchanges[1].source, "--mix");
    EXPECT_EQ(plan.exchanges[2].request, hex("00 00 00 00 00 06 01 06 00 10 12 34"));
    EXPECT_EQ(plan.mix_cumulative, (std::vector<std::uint64_t>{3, 4}));
}

TEST(LoadPlan, DurationWords) {
    EXPECT_EQ(format_duration_words(milliseconds(3'600'000)), "1 h");
    EXPECT_EQ(format_duration_words(milliseconds(5'430'000)), "1 h 30 min 30 s");
    EXPECT_EQ(format_duration_words(milliseconds(2000)), "2 s");
    EXPECT_EQ(format_duration_words(milliseconds(1500)), "1.5 s");
}

}  // namespace
}  // namespace mblab::load
