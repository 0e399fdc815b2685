#pragma once

#include <toml++/toml.h>

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

// Shared by the catalogue and DUT loaders: every complaint names the file and line.
namespace mblab::conformance {

class TomlReader {
  public:
    explicit TomlReader(std::string file) : file_(std::move(file)) {}

    const std::string& file() const { return file_; }
    // Parses the file or text; on a syntax error records it and returns nullopt.
    std::optional<toml::table> parse_file();
    std::optional<toml::table> parse_text(std::string_view text);

    // Records "file:line: reason" (first error only) and returns false so callers can chain.
    bool fail(const toml::node* at, const std::string& reason);
    bool fail_line(std::uint32_t line, const std::string& reason);
    bool failed() const { return !error_.empty(); }
    const std::string& error() const { return error_; }

    // Refuses keys outside `known`, naming the first unknown one.
    bool only_keys(const toml::table& table, const std::vector<std::string_view>& known);

    // Typed getters: absent keys leave `out` alone and succeed; wrong types or values fail.
    bool get(const toml::table& table, std::string_view key, std::string& out);
    bool get(const toml::table& table, std::string_view key, bool& out);
    bool get(const toml::table& table, std::string_view key, std::int64_t& out, std::int64_t min,
             std::int64_t max);
    template <class T>
    bool get_number(const toml::table& table, std::string_view key, std::optional<T>& out,
                    std::int64_t min, std::int64_t max) {
        if (!table.contains(key)) return true;
        std::int64_t value = 0;
        if (!get(table, key, value, min, max)) return false;
        out = static_cast<T>(value);
        return true;
    }
    // A string or an array of strings (each kept with its node for later complaints).
    bool get_strings(const toml::table& table, std::string_view key,
                     std::vector<std::pair<std::string, const toml::node*>>& out);

  private:
    std::string file_;
    std::string error_;
};

}  // namespace mblab::conformance
