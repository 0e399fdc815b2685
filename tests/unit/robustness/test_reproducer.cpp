#include <gtest/gtest.h>

#include "robustness/reproducer.hpp"

namespace mblab::robustness {
namespace {

TEST(Reproducer, WritesAndReadsTheSameSteps) {
    const std::vector<Step> steps = {
        {0, {0x00, 0x01, 0x00, 0x01, 0x00, 0x06, 0x01, 0x03}, std::chrono::milliseconds(20)},
        {2, {0xFF}, {}}};
    const auto text = reproducer_text(steps, "protocol-id: protocol id 0x0001\nsecond line");
    EXPECT_EQ(text,
              "# protocol-id: protocol id 0x0001\n"
              "# second line\n"
              "00 01 00 01 00 06 01 03 +20ms\n"
              "@2 FF\n");
    const auto parsed = parse_reproducer(text);
    ASSERT_TRUE(parsed) << parsed.error();
    ASSERT_EQ(parsed->size(), 2U);
    EXPECT_EQ((*parsed)[0].bytes, steps[0].bytes);
    EXPECT_EQ((*parsed)[0].pause, std::chrono::milliseconds(20));
    EXPECT_EQ((*parsed)[1].connection, 2U);
}

TEST(Reproducer, ABadLineIsNamed) {
    EXPECT_EQ(parse_reproducer("00 01\n0G\n").error(),
              "line 2: '0G' is not a byte: give two hex digits a byte (00 01 FF)");
    EXPECT_EQ(parse_reproducer("# nothing\n").error(),
              "no steps: a reproducer has a line of hex bytes");
    EXPECT_EQ(parse_reproducer("@x 00\n").error(),
              "line 1: '@x' is not a connection number (@1, @2, ...)");
}

}  // namespace
}  // namespace mblab::robustness
