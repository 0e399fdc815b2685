#pragma once

#include <cstddef>
#include <vector>

namespace mblab::robustness {

// The first of each list, then the second of each, ...: a budget cut short still reaches every
// list (every class of the fixed cases, every function of the pairwise ones).
template <typename T>
std::vector<T> in_turn(std::vector<std::vector<T>> lists) {
    std::vector<T> out;
    for (std::size_t round = 0;; ++round) {
        bool any = false;
        for (auto& list : lists) {
            if (round < list.size()) {
                out.push_back(std::move(list[round]));
                any = true;
            }
        }
        if (!any) return out;
    }
}

}  // namespace mblab::robustness
