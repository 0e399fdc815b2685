#include "cli/terminal_style.hpp"

#include <unistd.h>

#include <cstdlib>

namespace mblab::cli {

bool styles_wanted(int fd) {
    const char* no_color = std::getenv("NO_COLOR");
    return ::isatty(fd) != 0 && (no_color == nullptr || *no_color == '\0');
}

}  // namespace mblab::cli
