#include <gtest/gtest.h>

#include <algorithm>

#include "robustness/minimise.hpp"

namespace mblab::robustness {
namespace {

bool contains(const std::vector<std::size_t>& at, std::size_t index) {
    return std::find(at.begin(), at.end(), index) != at.end();
}

// A fake device that dies when frame 13 reaches it: found alone among 40.
TEST(Minimise, FindsTheOneKillingFrame) {
    std::size_t tries = 0;
    const auto kept = minimise(40, [&](const std::vector<std::size_t>& at) {
        ++tries;
        return contains(at, 13);
    });
    EXPECT_EQ(kept, (std::vector<std::size_t>{13}));
    EXPECT_LE(tries, 20U);
}

// Dies only when frame 3 comes and frame 9 follows it: both kept, in order.
TEST(Minimise, KeepsAPairThatKillsTogether) {
    const auto kept = minimise(
        16, [](const std::vector<std::size_t>& at) { return contains(at, 3) && contains(at, 9); });
    EXPECT_EQ(kept, (std::vector<std::size_t>{3, 9}));
}

TEST(Minimise, StopsAfterItsBudget) {
    std::size_t tries = 0;
    const auto kept = minimise(
        64,
        [&](const std::vector<std::size_t>& at) {
            ++tries;
            return at.size() > 10;
        },
        5);
    EXPECT_EQ(tries, 5U);
    EXPECT_GT(kept.size(), 10U);
}

}  // namespace
}  // namespace mblab::robustness
