#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "device/profile_loader.hpp"

// A register map as CSV (one point per row: address, bank, type, name, behaviour and its
// parameters, as docs/profiles.md "Register maps from CSV" describes) turned into profile TOML.
// The text is checked by the profile loader before it is returned, so what comes out loads; an
// error names the CSV file, the line and the column.
namespace mblab::device {

// The largest CSV file read: a whole map (4 banks x 65536 points) at a few dozen bytes a row is
// tens of megabytes, and a bound keeps an endless input (/dev/zero, a pipe) from being read
// forever.
constexpr std::size_t kMaxCsvBytes = std::size_t{128} << 20;

struct CsvImport {
    std::string source;  // the CSV file's name, for messages and the profile's header
    std::string name;    // the profile's name
    std::uint8_t unit = 1;
};

struct ImportedProfile {
    std::string toml;
};

Loaded<ImportedProfile> register_map_to_profile(std::string_view csv, const CsvImport& import);

}  // namespace mblab::device
