#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <utility>

#include "robustness/writable_range.hpp"

// What `mblab fuzz` reads besides its options: a writable range's text, files, a local
// process's memory, and the user's restart command's status.
namespace mblab::cli {

// "START:COUNT" or "START" (one register); nullopt when it is neither or runs past 0xFFFF.
std::optional<robustness::WritableRange> parse_writable(const std::string& text);
// The whole file into `text`; false when it cannot be read.
bool read_file(const std::string& path, std::string& text);
// VmRSS and VmHWM of a local process in kB, from /proc; nullopt when it is gone.
std::optional<std::pair<std::size_t, std::size_t>> process_memory(int pid);
// The --restart command, through the shell; true when it exited 0.
bool run_restart(const std::string& command);

}  // namespace mblab::cli
