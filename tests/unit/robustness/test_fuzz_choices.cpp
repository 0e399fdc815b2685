#include <gtest/gtest.h>

#include "robustness/class_choice.hpp"
#include "robustness/fuzz_progress.hpp"

// What the command line chooses of a run (its classes) and how it shows its progress.
namespace mblab::robustness {
namespace {

using namespace std::chrono_literals;

bool has(const ClassChoice& choice, BadInput kind) {
    return choice[static_cast<std::size_t>(kind)];
}

TEST(ClassChoice, EveryClassLessTheSkippedOrTheNamedOnes) {
    const auto all = choose_classes({}, {"flood,slow-reader", "many-connections"});
    ASSERT_TRUE(all) << all.error();
    EXPECT_FALSE(has(*all, BadInput::Flood));
    EXPECT_FALSE(has(*all, BadInput::SlowReader));
    EXPECT_FALSE(has(*all, BadInput::ManyConnections));
    EXPECT_TRUE(has(*all, BadInput::Mutation));
    const auto only = choose_classes({"quantity,pairwise", "mutation"}, {"mutation"});
    ASSERT_TRUE(only) << only.error();
    std::size_t chosen = 0;
    for (bool on : *only)
        chosen += on ? 1 : 0;
    EXPECT_EQ(chosen, 2U);
    EXPECT_TRUE(has(*only, BadInput::Quantity));
    EXPECT_TRUE(has(*only, BadInput::Pairwise));
}

TEST(ClassChoice, AnUnknownClassIsOneLineNamingTheClasses) {
    const auto wrong = choose_classes({"quantity", "floods"}, {});
    ASSERT_FALSE(wrong);
    EXPECT_EQ(wrong.error().find("--class 'floods' is not a class; the classes are protocol-id, "
                                 "mbap-length, oversize, "),
              0U)
        << wrong.error();
    EXPECT_TRUE(wrong.error().ends_with(", pairwise, mutation")) << wrong.error();
    EXPECT_EQ(wrong.error().find('\n'), std::string::npos);
    const auto skipped = choose_classes({}, {"nope"});
    ASSERT_FALSE(skipped);
    EXPECT_EQ(skipped.error().find("--skip-class 'nope' is not a class"), 0U);
}

TEST(FuzzProgress, DoneOutOfTheTotalAndTheTimeLeft) {
    // 100 of 1000 in 10 s: 900 more at that pace.
    EXPECT_EQ(progress_text(100, {1000, std::nullopt}, 10s, "quantity: FC 0x03 quantity 0"),
              "case 100/1000, about 1m 30s left: quantity: FC 0x03 quantity 0");
    // The time budget ends it first.
    EXPECT_EQ(progress_text(100, {1000, 30s}, 10s, "x"), "case 100/1000, about 20s left: x");
    EXPECT_EQ(progress_text(7, {std::nullopt, 2h}, 1h, "x"), "case 7, about 1h 00m left: x");
    EXPECT_EQ(progress_text(0, {1000, std::nullopt}, 0s, "x"), "case 0/1000: x");
}

}  // namespace
}  // namespace mblab::robustness
