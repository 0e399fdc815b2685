#pragma once

#include <cstdint>

// Below every layer: the reference device draws its faults from it, the load generator its mix
// and its send spread. Neither is the other's helper, so it lives with neither.
namespace mblab {

// SplitMix64: tiny, fully specified, so a fault seed replays the same run on every platform
// (std::uniform_*_distribution results differ between standard libraries).
class Prng {
  public:
    explicit Prng(std::uint64_t seed = 1) : state_(seed) {}

    std::uint64_t next() {
        std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ULL);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
        return z ^ (z >> 31);
    }
    // True with probability p (0..1), from the top 53 bits.
    bool chance(double p) {
        if (p >= 1.0) return true;
        if (p <= 0.0) return false;
        return static_cast<double>(next() >> 11) * 0x1.0p-53 < p;
    }

  private:
    std::uint64_t state_;
};

}  // namespace mblab
