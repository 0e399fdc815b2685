#pragma once

#include <span>
#include <string_view>

// The shipped catalogue/*.toml and profiles/*.toml, compiled into the binary at build time
// (cmake/embed_data.cmake), so that a binary copied anywhere still has them.
namespace mblab::shipped {

struct EmbeddedFile {
    std::string_view name;  // relative to the data directory: "catalogue/policy-2.1.toml"
    std::string_view text;
};

std::span<const EmbeddedFile> embedded_files();

}  // namespace mblab::shipped
