#include <gtest/gtest.h>

#include "conformance/catalogue.hpp"
#include "conformance/load_plan.hpp"
#include "support/hex.hpp"

namespace mblab::conformance {
namespace {

using std::chrono::milliseconds;
using test::hex;

Suite policy() {
    auto suite = load_suite_file(std::string(MBLAB_SOURCE_DIR) + "/catalogue/policy-2.1.toml");
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
    Dut dut;
    dut.unit = 1;
    dut.registers = 65536;
    ASSERT_TRUE(add_protocol_tests(plan, {policy()}, dut, {}).ok());
    EXPECT_EQ(ids(plan), (std::vector<std::string>{"7.3.1", "7.4.1", "7.5.1", "7.6.1", "7.7.1",
                                                   "7.8.1", "7.9.1", "7.10.1", "7.11.1", "7.12.1",
                                                   "9.1.1", "9.1.2", "9.1.4"}));
    EXPECT_EQ(plan.test_exchanges, 13U);
    std::vector<std::pair<std::string, std::string>> left;
    for (const auto& item : plan.left_out)
        left.emplace_back(item.id, item.reason);
    EXPECT_EQ(left, (std::vector<std::pair<std::string, std::string>>{
                        {"7.2", "procedure ping"},
                        {"7.5.2", "procedure register_sweep"},
                        {"7.13.1", "N/A: the DUT does not declare object_messaging"},
                        {"7.13.2", "procedure semi_signature_scan"},
                        {"9.1.3", "needs a connection of its own"}}));
    const LoadExchange& read = plan.exchanges[2];
    EXPECT_EQ(read.name, "7.5.1");
    EXPECT_EQ(read.source, "seed 000 7.5.1");
    EXPECT_EQ(read.request, hex("00 00 00 00 00 06 01 03 00 00 00 01"));
    ASSERT_EQ(read.answers.size(), 1U);
    EXPECT_TRUE(read.answers[0].matches(hex("AB CD 00 00 00 05 01 03 02 00 00")));
    // 9.1.2 reads past the declared registers: all 65536 are there, so two from 0xFFFF.
    EXPECT_EQ(plan.exchanges[11].request, hex("00 00 00 00 00 06 01 03 FF FF 00 02"));
    // 9.1.4 accepts 02 as well as 03.
    EXPECT_EQ(plan.exchanges[12].answers.size(), 2U);
}

TEST(LoadPlan, CaseChoiceAndMultiStepCases) {
    LoadPlan plan;
    auto suite = load_suite_file(std::string(MBLAB_SOURCE_DIR) + "/catalogue/function-codes.toml");
    ASSERT_TRUE(suite.ok()) << suite.error();
    Dut dut;
    dut.registers = 65536;
    ASSERT_TRUE(add_protocol_tests(plan, {policy(), suite.value()}, dut, {"7.8.1", "fc01.1"}).ok());
    EXPECT_EQ(ids(plan), (std::vector<std::string>{"7.8.1", "fc01.1"}));
    EXPECT_TRUE(plan.cases[1].unsupported_is_na);
    EXPECT_TRUE(plan.exchanges[1].first_step);
    EXPECT_EQ(plan.exchanges[1].test_case, 1U);

    LoadPlan missing;
    auto error = add_protocol_tests(missing, {policy()}, dut, {"7.99"});
    ASSERT_FALSE(error.ok());
    EXPECT_EQ(error.error(), "no case 7.99 in the chosen suites");
}

TEST(LoadPlan, MixFollowsTheTests) {
    LoadPlan plan;
    Dut dut;
    ASSERT_TRUE(add_protocol_tests(plan, {policy()}, dut, {"7.3.1"}).ok());
    add_mix(plan, parse_mix("fc3:2=3,fc6=1").value(), dut);
    ASSERT_EQ(plan.exchanges.size(), 3U);
    EXPECT_EQ(plan.exchanges[1].name, "fc3:2");
    EXPECT_EQ(plan.exchanges[1].source, "--mix");
    EXPECT_EQ(plan.exchanges[2].request, hex("00 00 00 00 00 06 00 06 00 10 12 34"));
    EXPECT_EQ(plan.mix_cumulative, (std::vector<std::uint64_t>{3, 4}));
}

TEST(LoadPlan, Durations) {
    EXPECT_EQ(parse_duration("1h").value(), milliseconds(3'600'000));
    EXPECT_EQ(parse_duration("10m").value(), milliseconds(600'000));
    EXPECT_EQ(parse_duration("30s").value(), milliseconds(30'000));
    EXPECT_EQ(parse_duration("1500ms").value(), milliseconds(1500));
    EXPECT_EQ(parse_duration("1h30m").value(), milliseconds(5'400'000));
    EXPECT_EQ(parse_duration("45").value(), milliseconds(45'000));
    for (auto bad : {"", "h", "1x", "1h30", "-5s", "0s", "1.5s"}) {
        EXPECT_FALSE(parse_duration(bad).ok()) << bad;
    }
    EXPECT_EQ(parse_duration("1x").error(),
              "bad duration '1x' (expected e.g. 1h, 10m, 30s, 1500ms or 1h30m)");
    EXPECT_EQ(format_duration_words(milliseconds(3'600'000)), "1 h");
    EXPECT_EQ(format_duration_words(milliseconds(5'430'000)), "1 h 30 min 30 s");
    EXPECT_EQ(format_duration_words(milliseconds(2000)), "2 s");
    EXPECT_EQ(format_duration_words(milliseconds(1500)), "1.5 s");
}

}  // namespace
}  // namespace mblab::conformance
