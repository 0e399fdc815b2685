// Fault rules: every Nth request, probability with a fixed seed, per function and address range.
#include <gtest/gtest.h>

#include "device_harness.hpp"

namespace mblab::test {
namespace {

constexpr std::string_view kMap = R"(
[[unit]]
id = 1
holding_registers = [{start = 0, count = 200}]
input_registers = [{start = 0, count = 10}]
)";

std::unique_ptr<device::ReferenceDevice> with_faults(std::string_view faults,
                                                     std::string_view seed = "fault_seed = 1") {
    return device_from(std::string(seed) + "\n" + std::string(kMap) + std::string(faults));
}

TEST(FaultRules, EveryNthRequestOfAFunctionGetsBusy) {
    auto device = with_faults(R"(
[[unit.faults]]
action = "exception"
exception = 6
every = 3
functions = [3]
)");
    std::string seen;
    for (int i = 0; i < 6; ++i)
        seen += ask(*device, "03 00 00 00 01") + "|";
    EXPECT_EQ(seen, "03 02 00 00|03 02 00 00|83 06|03 02 00 00|03 02 00 00|83 06|");
    EXPECT_EQ(ask(*device, "06 00 00 00 01"), "06 00 00 00 01");
    EXPECT_EQ(ask(*device, "08 00 11 00 00"), "08 00 11 00 02");
    EXPECT_EQ(ask(*device, "08 00 0D 00 00"), "08 00 0D 00 02");
}

TEST(FaultRules, AddressRangeFilterMatchesOverlappingRequests) {
    auto device = with_faults(R"(
[[unit.faults]]
action = "drop"
addresses = [100, 199]
)");
    EXPECT_EQ(ask(*device, "03 00 00 00 0A").substr(0, 5), "03 14");
    EXPECT_EQ(ask(*device, "03 00 96 00 01"), "NO ANSWER");
    EXPECT_EQ(ask(*device, "03 00 5F 00 0A"), "NO ANSWER");
    EXPECT_EQ(ask(*device, "06 00 64 00 01"), "NO ANSWER");
    EXPECT_EQ(ask(*device, "07"), "07 00");
    EXPECT_EQ(device->counters().stats(1)->counters.no_response, 3);
}

TEST(FaultRules, DelayAnswersNormallyLater) {
    auto device = with_faults(R"(
[[unit.faults]]
action = "delay"
delay_ms = 250
functions = [6]
)");
    std::string response;
    auto reply = ask_reply(*device, "06 00 01 00 02", response);
    EXPECT_EQ(response, "06 00 01 00 02");
    EXPECT_EQ(reply.delay, std::chrono::milliseconds(250));
    reply = ask_reply(*device, "03 00 01 00 01", response);
    EXPECT_EQ(response, "03 02 00 02");
    EXPECT_EQ(reply.delay, std::chrono::milliseconds(0));
}

TEST(FaultRules, CloseAndDeviceFailure) {
    auto device = with_faults(R"(
[[unit.faults]]
action = "close"
functions = [16]
[[unit.faults]]
action = "exception"
functions = [4]
)");
    EXPECT_EQ(ask(*device, "10 00 00 00 01 02 00 01"), "CLOSE");
    EXPECT_EQ(ask(*device, "04 00 00 00 01"), "84 04");
    EXPECT_EQ(ask(*device, "03 00 00 00 01"), "03 02 00 00");  // the close wrote nothing
}

TEST(FaultRules, GarbageIsReproducibleFromTheSeed) {
    constexpr std::string_view rule = R"(
[[unit.faults]]
action = "garbage"
garbage_bytes = 5
)";
    auto first = with_faults(rule, "fault_seed = 7");
    auto second = with_faults(rule, "fault_seed = 7");
    auto other = with_faults(rule, "fault_seed = 8");
    const std::string answer = ask(*first, "03 00 00 00 01");
    EXPECT_EQ(answer.size(), 5u * 3 - 1);
    EXPECT_EQ(ask(*second, "03 00 00 00 01"), answer);
    EXPECT_NE(ask(*other, "03 00 00 00 01"), answer);
}

std::string pattern(device::ReferenceDevice& device) {
    std::string out;
    for (int i = 0; i < 200; ++i)
        out += ask(device, "04 00 00 00 01") == "84 06" ? 'x' : '.';
    return out;
}

TEST(FaultRules, ProbabilityIsDeterministicForASeed) {
    constexpr std::string_view rule = R"(
[[unit.faults]]
action = "exception"
exception = 6
probability = 0.25
)";
    auto first = with_faults(rule, "fault_seed = 99");
    auto second = with_faults(rule, "fault_seed = 99");
    const std::string a = pattern(*first);
    EXPECT_EQ(a, pattern(*second));
    const auto fired = std::count(a.begin(), a.end(), 'x');
    EXPECT_GT(fired, 20);
    EXPECT_LT(fired, 80);
}

TEST(FaultRules, ProbabilityZeroNeverFires) {
    auto device = with_faults(R"(
[[unit.faults]]
action = "exception"
exception = 6
probability = 0.0
)");
    EXPECT_EQ(pattern(*device), std::string(200, '.'));
}

TEST(FaultRules, FirstFiringRuleWins) {
    auto device = with_faults(R"(
[[unit.faults]]
action = "exception"
exception = 6
every = 2
[[unit.faults]]
action = "exception"
exception = 4
)");
    EXPECT_EQ(ask(*device, "03 00 00 00 01"), "83 04");
    EXPECT_EQ(ask(*device, "03 00 00 00 01"), "83 06");
}

}  // namespace
}  // namespace mblab::test
