#pragma once

#include <filesystem>

// Where the shipped data (catalogue/, profiles/) is read from.
namespace mblab::shipped {

// The directory `name` ("catalogue" or "profiles"), first found of:
//   $env_var (a directory of that kind), $MBLAB_DATA_DIR/<name>,
//   the source tree's <name> when the running binary is in the build tree it was built in,
//   the installed data directory (<prefix>/share/mblab/<name>, the prefix being the binary's own
//   ../ first, then the configured install prefix),
//   the copies compiled into the binary, written out once to a private temporary directory that
//   is removed at exit.
std::filesystem::path data_dir(const char* env_var, const char* name);

}  // namespace mblab::shipped
