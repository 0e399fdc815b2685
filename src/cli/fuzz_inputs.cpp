#include "cli/fuzz_inputs.hpp"

#include <fmt/core.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

namespace mblab::cli {

std::optional<robustness::WritableRange> parse_writable(const std::string& text) {
    const auto colon = text.find(':');
    try {
        std::size_t used = 0;
        const auto start = std::stoul(text.substr(0, colon), &used, 0);
        if (used != text.substr(0, colon).size() || start > 0xFFFF) return std::nullopt;
        unsigned long count = 1;
        if (colon != std::string::npos) {
            const auto rest = text.substr(colon + 1);
            count = std::stoul(rest, &used, 0);
            if (used != rest.size() || count == 0 || start + count > 0x10000) return std::nullopt;
        }
        return robustness::WritableRange{static_cast<std::uint16_t>(start),
                                         static_cast<std::uint16_t>(count)};
    } catch (const std::exception&) {
        return std::nullopt;
    }
}

bool read_file(const std::string& path, std::string& text) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return false;
    std::stringstream buffer;
    buffer << in.rdbuf();
    text = buffer.str();
    return true;
}

std::optional<std::pair<std::size_t, std::size_t>> process_memory(int pid) {
    std::ifstream in(fmt::format("/proc/{}/status", pid));
    if (!in) return std::nullopt;
    std::size_t rss = 0;
    std::size_t peak = 0;
    for (std::string line; std::getline(in, line);) {
        if (line.starts_with("VmRSS:")) rss = std::stoul(line.substr(6));
        if (line.starts_with("VmHWM:")) peak = std::stoul(line.substr(6));
    }
    return std::pair{rss, peak};
}

bool run_restart(const std::string& command) {
    const int status = std::system(command.c_str());
    return status == 0;
}

}  // namespace mblab::cli
