#include "conformance/toml_reader.hpp"

#include <fmt/core.h>

#include <algorithm>

namespace mblab::conformance {

namespace {
std::string_view describe(std::string_view reason) {
    // toml++ ends some messages with a newline; the report puts one line per error.
    while (!reason.empty() && (reason.back() == '\n' || reason.back() == ' ')) {
        reason.remove_suffix(1);
    }
    return reason;
}
}  // namespace

std::optional<toml::table> TomlReader::parse_file() {
    try {
        return toml::parse_file(file_);
    } catch (const toml::parse_error& e) {
        const auto& source = e.source();
        if (source.begin.line == 0) {
            // toml++ reports an unreadable file without a position.
            error_ = fmt::format("{}: cannot read file", file_);
        } else {
            fail_line(source.begin.line, std::string(describe(e.description())));
        }
        return std::nullopt;
    }
}

std::optional<toml::table> TomlReader::parse_text(std::string_view text) {
    try {
        return toml::parse(text, file_);
    } catch (const toml::parse_error& e) {
        fail_line(e.source().begin.line, std::string(describe(e.description())));
        return std::nullopt;
    }
}

bool TomlReader::fail(const toml::node* at, const std::string& reason) {
    return fail_line(at != nullptr ? at->source().begin.line : 0, reason);
}

bool TomlReader::fail_line(std::uint32_t line, const std::string& reason) {
    if (error_.empty()) {
        error_ = line > 0 ? fmt::format("{}:{}: {}", file_, line, reason)
                          : fmt::format("{}: {}", file_, reason);
    }
    return false;
}

bool TomlReader::only_keys(const toml::table& table, const std::vector<std::string_view>& known) {
    for (const auto& [key, node] : table) {
        if (std::find(known.begin(), known.end(), key.str()) == known.end()) {
            std::string list;
            for (auto name : known)
                list += (list.empty() ? "" : ", ") + std::string(name);
            return fail(&node, fmt::format("unknown key '{}' (known keys: {})", key.str(), list));
        }
    }
    return true;
}

bool TomlReader::get(const toml::table& table, std::string_view key, std::string& out) {
    const toml::node* node = table.get(key);
    if (node == nullptr) return true;
    if (!node->is_string()) return fail(node, fmt::format("'{}' must be a string", key));
    out = node->as_string()->get();
    return true;
}

bool TomlReader::get(const toml::table& table, std::string_view key, bool& out) {
    const toml::node* node = table.get(key);
    if (node == nullptr) return true;
    if (!node->is_boolean()) return fail(node, fmt::format("'{}' must be true or false", key));
    out = node->as_boolean()->get();
    return true;
}

bool TomlReader::get(const toml::table& table, std::string_view key, std::int64_t& out,
                     std::int64_t min, std::int64_t max) {
    const toml::node* node = table.get(key);
    if (node == nullptr) return true;
    if (!node->is_integer() || node->as_integer()->get() < min || node->as_integer()->get() > max) {
        return fail(node, fmt::format("'{}' must be an integer from {} to {}", key, min, max));
    }
    out = node->as_integer()->get();
    return true;
}

bool TomlReader::get_strings(const toml::table& table, std::string_view key,
                             std::vector<std::pair<std::string, const toml::node*>>& out) {
    const toml::node* node = table.get(key);
    if (node == nullptr) return true;
    if (node->is_string()) {
        out.emplace_back(node->as_string()->get(), node);
        return true;
    }
    if (const toml::array* array = node->as_array()) {
        for (const toml::node& item : *array) {
            if (!item.is_string()) {
                return fail(&item, fmt::format("'{}' must hold strings only", key));
            }
            out.emplace_back(item.as_string()->get(), &item);
        }
        return true;
    }
    return fail(node, fmt::format("'{}' must be a string or an array of strings", key));
}

}  // namespace mblab::conformance
