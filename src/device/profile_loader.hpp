#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "device/profile.hpp"
#include "protocol/result.hpp"

// Profiles are TOML (docs/profiles.md). A profile that cannot be used is refused with one line:
// "FILE:LINE: KEY: what is wrong and what is expected".
namespace mblab::device {

template <class T>
using Loaded = protocol::Result<T, std::string>;

// `source` names the text in messages (a file name, or e.g. "<test>").
Loaded<Profile> parse_profile(std::string_view text, std::string_view source);
Loaded<Profile> read_profile(const std::filesystem::path& path);

// Names used in profiles and messages.
std::string_view bank_key(BankKind kind);
bool is_bit_bank(BankKind kind);

}  // namespace mblab::device
