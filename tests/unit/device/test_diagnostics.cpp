// FC 08 counters after a sequence, listen-only mode and restart, FC 0B / 0C event counter and log.
#include <gtest/gtest.h>

#include "device_harness.hpp"

namespace mblab::test {
namespace {

class Diagnostics : public ShippedDeviceTest {
  protected:
    Diagnostics() : ShippedDeviceTest("reference") {}
};

TEST_F(Diagnostics, CountsMessagesAndExceptions) {
    expect_dialogue(R"(
        03 00 00 00 01 -> 03 02 53 45
        03 00 00 FF FF -> 83 03
        08 00 0B 00 00 -> 08 00 0B 00 03
        08 00 0D 00 00 -> 08 00 0D 00 01
        08 00 0E 00 00 -> 08 00 0E 00 05
        08 00 0F 00 00 -> 08 00 0F 00 00
        08 00 10 00 00 -> 08 00 10 00 00
        08 00 11 00 00 -> 08 00 11 00 00
    )");
}

TEST_F(Diagnostics, CountsLineErrorsAndOverruns) {
    device->counters().count_crc_error();
    device->counters().count_short_frame();
    device->counters().count_parity_error();
    device->counters().count_overrun();
    expect_dialogue(R"(
        08 00 0C 00 00 -> 08 00 0C 00 03
        08 00 12 00 00 -> 08 00 12 00 01
        08 00 14 00 00 -> 08 00 14 00 00
        08 00 12 00 00 -> 08 00 12 00 00
        08 00 0C 00 00 -> 08 00 0C 00 03
    )");
}

TEST_F(Diagnostics, ClearCountersTakesEffectAfterItsAnswer) {
    EXPECT_EQ(ask("03 00 00 FF FF"), "83 03");
    device->counters().count_crc_error();
    expect_dialogue(R"(
        08 00 0A 00 00 -> 08 00 0A 00 00
        08 00 0B 00 00 -> 08 00 0B 00 01
        08 00 0C 00 00 -> 08 00 0C 00 00
        08 00 0D 00 00 -> 08 00 0D 00 00
    )");
}

TEST_F(Diagnostics, ReturnsRegisterAndChangesAsciiDelimiter) {
    expect_dialogue(R"(
        08 00 02 00 00 -> 08 00 02 00 00
        08 00 03 3B 00 -> 08 00 03 3B 00
    )");
    EXPECT_EQ(device->counters().ascii_delimiter(1), ';');
}

TEST_F(Diagnostics, RejectsBadSubFunctionData) {
    expect_dialogue(R"(
        08 00 01 00 05 -> 88 03
        08 00 0B 00 01 -> 88 03
        08 00 15 00 00 -> 88 01
    )");
}

TEST_F(Diagnostics, ListenOnlyUntilRestart) {
    EXPECT_EQ(ask("08 00 04 00 00"), "NO ANSWER");
    EXPECT_TRUE(device->counters().stats(1)->listen_only);
    expect_dialogue(R"(
        03 00 00 00 01 -> NO ANSWER
        08 00 00 12 34 -> NO ANSWER
    )");
    EXPECT_EQ(device->counters().stats(1)->counters.no_response, 3);
    EXPECT_EQ(ask("08 00 01 00 00"), "NO ANSWER");  // restart leaves listen-only silently
    EXPECT_FALSE(device->counters().stats(1)->listen_only);
    expect_dialogue(R"(
        03 00 00 00 01 -> 03 02 53 45
        08 00 0B 00 00 -> 08 00 0B 00 02
    )");
}

TEST_F(Diagnostics, RestartAnswersThenClearsCountersAndLog) {
    expect_dialogue(R"(
        06 00 10 00 01 -> 06 00 10 00 01
        08 00 01 FF 00 -> 08 00 01 FF 00
        # The log holds the restart event, then this request's receive event.
        0C             -> 0C 08 00 00 00 00 00 01 80 00
    )");
}

TEST_F(Diagnostics, RestartWithoutClearKeepsTheLog) {
    expect_dialogue(R"(
        08 00 04 00 00 -> NO ANSWER
        03 00 00 00 01 -> NO ANSWER
        08 00 01 00 00 -> NO ANSWER
        # receive, listen-only entered, two receives in listen-only, restart, receive of this 0C
        0C             -> 0C 0C 00 00 00 00 00 01 80 00 A0 A0 04 80
    )");
}

TEST_F(Diagnostics, EventCounterCountsSuccessfulRequestsOnly) {
    expect_dialogue(R"(
        06 00 10 00 01 -> 06 00 10 00 01
        03 00 10 00 01 -> 03 02 00 01
        03 00 00 FF FF -> 83 03
        0B             -> 0B 00 00 00 02
        0B             -> 0B 00 00 00 02
    )");
}

TEST_F(Diagnostics, EventLogMarksExceptionsSent) {
    expect_dialogue(R"(
        03 00 00 FF FF -> 83 03
        0C             -> 0C 09 00 00 00 00 00 02 80 41 80
    )");
}

TEST_F(Diagnostics, EventLogKeepsTheNewestSixtyFourEvents) {
    for (int i = 0; i < 40; ++i)
        ASSERT_EQ(ask("07"), "07 00");
    const std::string log = ask("0C");
    EXPECT_EQ(log.substr(0, 20), "0C 46 00 00 00 28 00");  // 6 + 64 bytes, 40 events, 41 msgs
    EXPECT_EQ(log.size(), (2 + 6 + 64) * 3 - 1);
}

}  // namespace
}  // namespace mblab::test
