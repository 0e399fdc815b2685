#pragma once

#include <cstddef>

namespace mblab::protocol {

// A framer's error message with numbers in it, formatted into a fixed buffer so that reporting
// an error never allocates. The text lives until the next format().
class FrameErrorText {
  public:
    const char* format(const char* fmt, ...) __attribute__((format(printf, 2, 3)));
    const char* c_str() const { return text_; }

  private:
    char text_[128] = "";
};

}  // namespace mblab::protocol
