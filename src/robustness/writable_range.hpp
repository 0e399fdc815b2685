#pragma once

#include <cstdint>

namespace mblab::robustness {

// Holding registers (and coils at the same addresses) the tester may write.
struct WritableRange {
    std::uint16_t start = 0;
    std::uint16_t count = 0;
};

}  // namespace mblab::robustness
