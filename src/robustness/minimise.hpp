#pragma once

#include <cstddef>
#include <functional>
#include <vector>

// Delta debugging (Zeller's ddmin): the shortest subsequence of a failing sequence that still
// fails, found by removing chunks, then halving the chunk size. Pure: the caller's predicate does
// the replaying (a restarted device and the liveness check, or a fake in tests).
namespace mblab::robustness {

// Indices into the original sequence, ascending. `fails(indices)` says whether that
// subsequence still kills; it is assumed true for the whole sequence. Stops after `max_tries`
// calls with the shortest found so far.
std::vector<std::size_t> minimise(std::size_t size,
                                  const std::function<bool(const std::vector<std::size_t>&)>& fails,
                                  std::size_t max_tries = 200);

}  // namespace mblab::robustness
