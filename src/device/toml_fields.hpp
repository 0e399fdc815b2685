#pragma once

#include <toml++/toml.h>

#include <cstdint>
#include <initializer_list>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

// Reading a profile's TOML tables with errors a user can act on: every problem becomes one line
// "FILE:LINE: PATH: what was expected, got what", and only the first problem is kept so the
// message points at the cause rather than at its consequences.
namespace mblab::device {

class ProfileErrors {
  public:
    explicit ProfileErrors(std::string source) : source_(std::move(source)) {}

    void fail(const toml::source_region& where, std::string_view path, std::string_view message);
    bool failed() const { return !message_.empty(); }
    const std::string& message() const { return message_; }
    const std::string& source() const { return source_; }

  private:
    std::string source_;
    std::string message_;
};

// "an integer", "a string": how a node's type reads in a message.
std::string describe_node(const toml::node& node);

// One table of the profile. Getters leave the output alone when the key is absent and return
// whether the key was present and valid; finish() reports keys nobody asked for.
class Fields {
  public:
    Fields(const toml::table& table, std::string path, ProfileErrors& errors)
        : table_(table), path_(std::move(path)), errors_(errors) {}

    const toml::node* get(std::string_view key);
    bool has(std::string_view key) const { return table_.contains(key); }
    std::string path(std::string_view key) const;
    std::string path() const { return path_; }
    ProfileErrors& errors() { return errors_; }
    bool failed() const { return errors_.failed(); }

    // Reports at `key`'s line, or at the table's line when the key is absent.
    void fail(std::string_view key, std::string_view message);
    // Reports "missing key; <hint>" when `key` is absent; returns whether it is present.
    bool require(std::string_view key, std::string_view hint);

    bool integer(std::string_view key, std::int64_t& out, std::int64_t min, std::int64_t max);
    template <class T>
    bool integer_as(std::string_view key, T& out, std::int64_t min, std::int64_t max) {
        std::int64_t value = 0;
        if (!integer(key, value, min, max)) return false;
        out = static_cast<T>(value);
        return true;
    }
    bool number(std::string_view key, double& out, double min, double max);
    bool boolean(std::string_view key, bool& out);
    bool string(std::string_view key, std::string& out);
    bool table(std::string_view key, const toml::table*& out);
    bool array(std::string_view key, const toml::array*& out);

    template <class T>
    bool choice(std::string_view key, T& out,
                std::initializer_list<std::pair<std::string_view, T>> choices) {
        std::string text;
        if (!string(key, text)) return false;
        for (const auto& [name, value] : choices) {
            if (name == text) {
                out = value;
                return true;
            }
        }
        std::string names;
        for (const auto& [name, value] : choices) {
            if (!names.empty()) names += ", ";
            names += name;
        }
        fail(key, "expected one of " + names + ", got \"" + text + "\"");
        return false;
    }

    void finish();

  private:
    const toml::table& table_;
    std::string path_;
    ProfileErrors& errors_;
    std::vector<std::string> known_;
};

// Reads an integer element of an array (for lists of function codes, addresses, bytes).
bool array_integer(const toml::node& node, std::string_view path, std::int64_t min,
                   std::int64_t max, ProfileErrors& errors, std::int64_t& out);

// "[1, 247]" style inclusive ranges.
bool integer_pair(Fields& fields, std::string_view key, std::int64_t min, std::int64_t max,
                  std::int64_t& first, std::int64_t& last);

}  // namespace mblab::device
