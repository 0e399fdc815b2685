#include "robustness/minimise.hpp"

#include <algorithm>
#include <numeric>

namespace mblab::robustness {

std::vector<std::size_t> minimise(std::size_t size,
                                  const std::function<bool(const std::vector<std::size_t>&)>& fails,
                                  std::size_t max_tries) {
    std::vector<std::size_t> current(size);
    std::iota(current.begin(), current.end(), std::size_t{0});
    std::size_t tries = 0;
    std::size_t chunks = 2;
    while (current.size() >= 2 && tries < max_tries) {
        const std::size_t chunk = (current.size() + chunks - 1) / chunks;
        bool reduced = false;
        // Each chunk alone first (a single killing frame is found in log n steps), then each
        // complement.
        for (int pass = 0; pass < 2 && !reduced; ++pass) {
            for (std::size_t from = 0; from < current.size() && tries < max_tries; from += chunk) {
                const std::size_t to = std::min(from + chunk, current.size());
                std::vector<std::size_t> candidate;
                if (pass == 0) {
                    candidate.assign(current.begin() + static_cast<long>(from),
                                     current.begin() + static_cast<long>(to));
                } else {
                    candidate.assign(current.begin(), current.begin() + static_cast<long>(from));
                    candidate.insert(candidate.end(), current.begin() + static_cast<long>(to),
                                     current.end());
                }
                if (candidate.empty() || candidate.size() == current.size()) continue;
                ++tries;
                if (fails(candidate)) {
                    current = std::move(candidate);
                    chunks = pass == 0 ? 2 : std::max<std::size_t>(chunks - 1, 2);
                    reduced = true;
                    break;
                }
            }
        }
        if (!reduced) {
            if (chunk == 1) break;
            chunks = std::min(chunks * 2, current.size());
        }
    }
    return current;
}

}  // namespace mblab::robustness
