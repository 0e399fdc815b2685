#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>

#include "transport/serial_url.hpp"

// How much of a serial line a load run used, against what the line can carry. A character
// takes its bits at the baud rate [SER 2.5.1, 2.5.2], and RTU frames need t3.5 of silence
// between them [SER 2.5.1.1]; ASCII frames are cut by their characters, so they need none.
namespace mblab::load {

struct LineUse {
    double chars_per_second = 0;  // sent and heard, over the run's time
    double limit_per_second = 0;  // what the baud rate carries with these frames and silences
    double share = 0;             // chars_per_second / limit_per_second
    bool logical = false;         // a pty: it does not pace bytes, so the share may pass 1
};

// Nothing for RTU over TCP, which has no baud rate.
std::optional<LineUse> line_use(const transport::SerialUrl& url, std::uint64_t chars,
                                std::uint64_t frames, std::chrono::microseconds elapsed);

// "1104 characters/s, 87.0% of the 1269/s 19200 baud allows with t3.5 between frames".
std::string line_use_text(const transport::SerialUrl& url, const LineUse& use);

}  // namespace mblab::load
