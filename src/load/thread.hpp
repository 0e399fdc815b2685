#pragma once

#include <atomic>
#include <cstddef>

#include "load/tally.hpp"

namespace mblab::load {

// One thread of a load run: it runs until told to drain and keeps its own counts per node (no
// other thread writes them, so counting needs no lock).
class LoadThread {
  public:
    virtual ~LoadThread() = default;
    // Runs until `draining` is set and every request in flight is answered or timed out.
    virtual void run(const std::atomic<bool>& draining) = 0;
    virtual const NodeTally& tally(std::size_t node) const = 0;
};

}  // namespace mblab::load
