#pragma once

#include <cstddef>
#include <span>
#include <vector>

// Strength-2 covering arrays: rows in which every value of every parameter meets every value of
// every other parameter at least once, in far fewer rows than the full product (4 parameters of 3
// values: 9 rows for 81). Bugs that take two fields' values together are found by trying every
// pair, not every combination. Pure and deterministic: the same counts give the same rows.
namespace mblab::robustness {

// For each parameter, the index of its value.
using PairwiseRow = std::vector<std::size_t>;

// Rows covering every pair of values of the parameters, parameter i having value_counts[i]
// values. Value 0 of each parameter is its nominal one: wherever no pair needs a value, the row
// has value 0, so that the other values are tried against a request that is otherwise right.
// No rows when there is no parameter or a parameter has no value; one parameter gives a row per
// value.
std::vector<PairwiseRow> pairwise_rows(std::span<const std::size_t> value_counts);

}  // namespace mblab::robustness
