#pragma once

#include <cstdint>

namespace mblab::test {

// A loopback port nothing listens on (bound, then released): connecting to it is refused.
std::uint16_t closed_port();

}  // namespace mblab::test
