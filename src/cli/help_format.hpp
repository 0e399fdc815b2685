#pragma once

#include <CLI/CLI.hpp>
#include <string>

// --help in mblab's words: CLI11 names an option's value by its C++ type and the checks on it
// ("UINT:INT in [1 - 65536]", "TEXT:FILE", "TEXT:{app,frame,bytes}"); mblab shows what to type
// ("1..65536", "FILE", "app|frame|bytes").
namespace mblab::cli {

// The words for CLI11's type name of an option (its type, then ':' and each check's text).
std::string value_words(const std::string& cli11_type);

class HelpFormatter final : public CLI::Formatter {
  public:
    std::string make_option_opts(const CLI::Option* option) const override;
};

}  // namespace mblab::cli
