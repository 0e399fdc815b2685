#include "protocol/frame_error_text.hpp"

#include <cstdarg>
#include <cstdio>

namespace mblab::protocol {

const char* FrameErrorText::format(const char* fmt, ...) {
    va_list args;
    va_start(args, fmt);
    std::vsnprintf(text_, sizeof text_, fmt, args);
    va_end(args);
    return text_;
}

}  // namespace mblab::protocol
