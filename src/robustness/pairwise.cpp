#include "robustness/pairwise.hpp"

#include <algorithm>
#include <limits>
#include <numeric>

// In-parameter-order growth: the full product of the two largest parameters, then one parameter
// at a time, a value chosen for each existing row to cover the most pairs still missing
// (horizontal growth), then rows changed or added for the pairs left (vertical growth).
namespace mblab::robustness {

namespace {

// A position no pair has needed yet: vertical growth may still set it; in the end it is nominal.
constexpr std::size_t kFree = std::numeric_limits<std::size_t>::max();

// The pairs of column `k` with the columns before it that no row covers yet.
class Missing {
  public:
    Missing(std::span<const std::size_t> counts, std::size_t k) : counts_(counts), k_(k) {
        for (std::size_t j = 0; j < k; ++j) {
            needed_.emplace_back(counts[j] * counts[k], true);
            left_ += counts[j] * counts[k];
        }
    }

    bool needed(std::size_t j, std::size_t a, std::size_t b) const {
        return needed_[j][a * counts_[k_] + b];
    }

    // How many missing pairs `row` would cover with value `b` in column k.
    std::size_t gain(const PairwiseRow& row, std::size_t b) const {
        std::size_t n = 0;
        for (std::size_t j = 0; j < k_; ++j) {
            if (row[j] != kFree && needed(j, row[j], b)) ++n;
        }
        return n;
    }

    void cover(const PairwiseRow& row) {
        if (row[k_] == kFree) return;
        for (std::size_t j = 0; j < k_; ++j) {
            if (row[j] == kFree) continue;
            auto slot = needed_[j].begin() + static_cast<long>(row[j] * counts_[k_] + row[k_]);
            if (*slot) {
                *slot = false;
                --left_;
            }
        }
    }

    std::size_t left() const { return left_; }

  private:
    std::span<const std::size_t> counts_;
    std::size_t k_;
    std::vector<std::vector<bool>> needed_;
    std::size_t left_ = 0;
};

void grow_horizontally(std::vector<PairwiseRow>& rows, Missing& missing, std::size_t k,
                       std::size_t count) {
    for (auto& row : rows) {
        std::size_t best = kFree;
        std::size_t best_gain = 0;
        // Strictly more: ties go to the lower value, the nominal one first.
        for (std::size_t b = 0; b < count; ++b) {
            const auto gain = missing.gain(row, b);
            if (gain > best_gain) {
                best = b;
                best_gain = gain;
            }
        }
        // A row that covers nothing new keeps the column free for vertical growth.
        row[k] = best;
        missing.cover(row);
        if (missing.left() == 0) return;
    }
}

void grow_vertically(std::vector<PairwiseRow>& rows, Missing& missing,
                     std::span<const std::size_t> counts, std::size_t k) {
    for (std::size_t j = 0; j < k && missing.left() > 0; ++j) {
        for (std::size_t a = 0; a < counts[j]; ++a) {
            for (std::size_t b = 0; b < counts[k]; ++b) {
                if (!missing.needed(j, a, b)) continue;
                auto fits = [&](const PairwiseRow& row) {
                    return (row[j] == a || row[j] == kFree) && (row[k] == b || row[k] == kFree);
                };
                auto it = std::find_if(rows.begin(), rows.end(), fits);
                if (it == rows.end())
                    it = rows.insert(rows.end(), PairwiseRow(counts.size(), kFree));
                (*it)[j] = a;
                (*it)[k] = b;
                missing.cover(*it);
            }
        }
    }
}

}  // namespace

std::vector<PairwiseRow> pairwise_rows(std::span<const std::size_t> value_counts) {
    const std::size_t n = value_counts.size();
    if (n == 0 || std::find(value_counts.begin(), value_counts.end(), 0) != value_counts.end())
        return {};
    // Largest first: the first two parameters' product is the least the array can have, and the
    // smaller ones fit into its rows.
    std::vector<std::size_t> order(n);
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
        return value_counts[x] > value_counts[y];
    });
    std::vector<std::size_t> counts(n);
    for (std::size_t i = 0; i < n; ++i)
        counts[i] = value_counts[order[i]];

    std::vector<PairwiseRow> rows;
    if (n == 1) {
        for (std::size_t a = 0; a < counts[0]; ++a)
            rows.push_back({a});
        return rows;
    }
    for (std::size_t a = 0; a < counts[0]; ++a) {
        for (std::size_t b = 0; b < counts[1]; ++b) {
            PairwiseRow row(n, kFree);
            row[0] = a;
            row[1] = b;
            rows.push_back(std::move(row));
        }
    }
    for (std::size_t k = 2; k < n; ++k) {
        Missing missing(counts, k);
        grow_horizontally(rows, missing, k, counts[k]);
        grow_vertically(rows, missing, counts, k);
    }

    std::vector<PairwiseRow> out;
    out.reserve(rows.size());
    for (const auto& row : rows) {
        PairwiseRow original(n);
        for (std::size_t i = 0; i < n; ++i)
            original[order[i]] = row[i] == kFree ? 0 : row[i];
        out.push_back(std::move(original));
    }
    return out;
}

}  // namespace mblab::robustness
