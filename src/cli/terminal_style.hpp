#pragma once

// Whether output may carry ANSI styles: only on a terminal, and not when NO_COLOR is set to
// anything but the empty string (no-color.org).
namespace mblab::cli {

bool styles_wanted(int fd);

}  // namespace mblab::cli
