#include <gtest/gtest.h>

#include <functional>
#include <set>
#include <tuple>

#include "robustness/pairwise.hpp"

namespace mblab::robustness {
namespace {

using Counts = std::vector<std::size_t>;

std::size_t product(const Counts& counts) {
    std::size_t out = 1;
    for (auto count : counts)
        out *= count;
    return out;
}

// Checked by brute force: every row in range, every value of every two parameters together in
// some row, every value of every parameter in some row.
void expect_covering(const Counts& counts, const std::vector<PairwiseRow>& rows) {
    std::set<std::tuple<std::size_t, std::size_t, std::size_t, std::size_t>> seen;
    std::set<std::pair<std::size_t, std::size_t>> values;
    for (const auto& row : rows) {
        ASSERT_EQ(row.size(), counts.size());
        for (std::size_t i = 0; i < counts.size(); ++i) {
            ASSERT_LT(row[i], counts[i]);
            values.insert({i, row[i]});
            for (std::size_t j = i + 1; j < counts.size(); ++j)
                seen.insert({i, row[i], j, row[j]});
        }
    }
    for (std::size_t i = 0; i < counts.size(); ++i) {
        for (std::size_t a = 0; a < counts[i]; ++a) {
            EXPECT_TRUE(values.count({i, a})) << "parameter " << i << " value " << a;
            for (std::size_t j = i + 1; j < counts.size(); ++j) {
                for (std::size_t b = 0; b < counts[j]; ++b)
                    EXPECT_TRUE(seen.count({i, a, j, b}))
                        << "parameters " << i << ", " << j << " values " << a << ", " << b;
            }
        }
    }
}

TEST(Pairwise, EveryPairIsCoveredWhateverTheShape) {
    for (const Counts& counts : std::vector<Counts>{{2, 2},
                                                    {2, 2, 2},
                                                    {3, 3, 3, 3},
                                                    {6, 6, 6, 6, 6, 6},
                                                    {2, 7, 3, 5, 1, 4},
                                                    {8, 6, 6, 5, 3, 2},
                                                    {1, 1, 1},
                                                    {3, 1, 3},
                                                    {10, 2, 2, 2, 2, 2, 2},
                                                    {3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3}}) {
        SCOPED_TRACE(::testing::PrintToString(counts));
        const auto rows = pairwise_rows(counts);
        expect_covering(counts, rows);
        EXPECT_LE(rows.size(), product(counts));
    }
}

// Against the known optima: 3 parameters of 2 values take 4 rows, 4 of 3 values 9 (an orthogonal
// array). A greedy construction is near, not always at, the optimum.
TEST(Pairwise, SmallCasesAreAtOrNearTheOptimum) {
    EXPECT_EQ(pairwise_rows(Counts{2, 2, 2}).size(), 4U);
    EXPECT_LE(pairwise_rows(Counts{3, 3, 3, 3}).size(), 10U);
    // Two parameters need their product, no more.
    EXPECT_EQ(pairwise_rows(Counts{5, 4}).size(), 20U);
    // 13 parameters of 3 values: 15 is the best known, 1594323 the product.
    EXPECT_LE(pairwise_rows(Counts(13, 3)).size(), 22U);
}

TEST(Pairwise, FarFewerRowsThanTheProduct) {
    const Counts six(6, 6);
    const auto rows = pairwise_rows(six);
    // 36 is the least (the product of two); 46656 the full product.
    EXPECT_GE(rows.size(), 36U);
    EXPECT_LE(rows.size(), 60U);
    // The rows the fuzzer's requests take: 8 and 6 values for the PDU, then MBAP fields.
    const Counts request{6, 8, 5, 6, 2, 3};
    EXPECT_LE(pairwise_rows(request).size(), 56U);
    EXPECT_GT(product(request), 100 * pairwise_rows(request).size());
}

TEST(Pairwise, TheSameCountsGiveTheSameRows) {
    const Counts counts{4, 3, 5, 2, 2, 6};
    EXPECT_EQ(pairwise_rows(counts), pairwise_rows(counts));
}

// The order the caller gives is kept in each row, whatever order the construction used.
TEST(Pairwise, ColumnsStayInTheCallersOrder) {
    const Counts counts{2, 5, 3};
    for (const auto& row : pairwise_rows(counts)) {
        EXPECT_LT(row[0], 2U);
        EXPECT_LT(row[1], 5U);
        EXPECT_LT(row[2], 3U);
    }
}

// Value 0 is nominal: the first row is all nominal, and a parameter of one value has it in every
// row.
TEST(Pairwise, NominalValuesFillWhatNoPairNeeds) {
    const auto rows = pairwise_rows(Counts{3, 4, 2, 1});
    ASSERT_FALSE(rows.empty());
    EXPECT_EQ(rows.front(), (PairwiseRow{0, 0, 0, 0}));
    for (const auto& row : rows)
        EXPECT_EQ(row[3], 0U);
}

TEST(Pairwise, DegenerateShapes) {
    EXPECT_TRUE(pairwise_rows(Counts{}).empty());
    EXPECT_TRUE(pairwise_rows(Counts{3, 0, 2}).empty());
    EXPECT_EQ(pairwise_rows(Counts{4}), (std::vector<PairwiseRow>{{0}, {1}, {2}, {3}}));
    EXPECT_EQ(pairwise_rows(Counts{1}), (std::vector<PairwiseRow>{{0}}));
    EXPECT_EQ(pairwise_rows(Counts{1, 1, 1, 1}), (std::vector<PairwiseRow>{{0, 0, 0, 0}}));
    EXPECT_EQ(pairwise_rows(Counts{1, 3}).size(), 3U);
}

}  // namespace
}  // namespace mblab::robustness
