#pragma once

#include <cstddef>

// Whether output may carry ANSI styles: only on a terminal, and not when NO_COLOR is set to
// anything but the empty string (no-color.org).
namespace mblab::cli {

bool styles_wanted(int fd);

// The columns to fit output to: COLUMNS when it is set to a number, else the terminal's width
// when `fd` is one; 0 (lines are not cut) for a pipe or a file, whose reader (grep, a log) wants
// each line whole.
std::size_t terminal_width(int fd);

}  // namespace mblab::cli
