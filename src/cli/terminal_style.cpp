#include "cli/terminal_style.hpp"

#include <sys/ioctl.h>
#include <unistd.h>

#include <cstdlib>

namespace mblab::cli {

bool styles_wanted(int fd) {
    const char* no_color = std::getenv("NO_COLOR");
    return ::isatty(fd) != 0 && (no_color == nullptr || *no_color == '\0');
}

std::size_t terminal_width(int fd) {
    if (const char* columns = std::getenv("COLUMNS"); columns != nullptr && *columns != '\0') {
        char* end = nullptr;
        const unsigned long value = std::strtoul(columns, &end, 10);
        if (*end == '\0' && value > 0) return value;
    }
    winsize size{};
    if (::isatty(fd) != 0 && ::ioctl(fd, TIOCGWINSZ, &size) == 0) return size.ws_col;
    return 0;
}

}  // namespace mblab::cli
