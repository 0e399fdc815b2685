#include "device/toml_fields.hpp"

#include <algorithm>
#include <sstream>

namespace mblab::device {

namespace {
std::string format_number(double value) {
    std::ostringstream out;
    out << value;
    return out.str();
}
}  // namespace

void ProfileErrors::fail(const toml::source_region& where, std::string_view path,
                         std::string_view message) {
    if (failed()) return;
    message_ = source_ + ":" + std::to_string(where.begin.line) + ": ";
    if (!path.empty()) {
        message_ += path;
        message_ += ": ";
    }
    message_ += message;
}

std::string describe_node(const toml::node& node) {
    switch (node.type()) {
        case toml::node_type::table:
            return "a table";
        case toml::node_type::array:
            return "an array";
        case toml::node_type::string:
            return "the string \"" + **node.as_string() + "\"";
        case toml::node_type::integer:
            return std::to_string(**node.as_integer());
        case toml::node_type::floating_point:
            return format_number(**node.as_floating_point());
        case toml::node_type::boolean:
            return **node.as_boolean() ? "true" : "false";
        case toml::node_type::date:
        case toml::node_type::time:
        case toml::node_type::date_time:
            return "a date or time";
        case toml::node_type::none:
            break;
    }
    return "nothing";
}

const toml::node* Fields::get(std::string_view key) {
    known_.emplace_back(key);
    return table_.get(key);
}

std::string Fields::path(std::string_view key) const {
    if (path_.empty()) return std::string(key);
    return path_ + "." + std::string(key);
}

void Fields::fail(std::string_view key, std::string_view message) {
    const toml::node* node = table_.get(key);
    errors_.fail(node ? node->source() : table_.source(), path(key), message);
}

bool Fields::require(std::string_view key, std::string_view hint) {
    if (has(key)) return true;
    errors_.fail(table_.source(), path(key), "missing key; " + std::string(hint));
    return false;
}

bool Fields::integer(std::string_view key, std::int64_t& out, std::int64_t min, std::int64_t max) {
    const toml::node* node = get(key);
    if (!node) return false;
    return array_integer(*node, path(key), min, max, errors_, out);
}

bool Fields::number(std::string_view key, double& out, double min, double max) {
    const toml::node* node = get(key);
    if (!node) return false;
    double value = 0;
    if (auto i = node->as_integer()) {
        value = static_cast<double>(**i);
    } else if (auto f = node->as_floating_point()) {
        value = **f;
    } else {
        fail(key, "expected a number, got " + describe_node(*node));
        return false;
    }
    if (!(value >= min && value <= max)) {
        fail(key, "expected a number from " + format_number(min) + " to " + format_number(max) +
                      ", got " + describe_node(*node));
        return false;
    }
    out = value;
    return true;
}

namespace {

// The node under `key` as the type `as` asks for; reports any other type.
template <class As>
auto typed(Fields& fields, std::string_view key, std::string_view expected, As as)
    -> decltype(as(std::declval<const toml::node&>())) {
    const toml::node* node = fields.get(key);
    if (!node) return nullptr;
    auto value = as(*node);
    if (!value)
        fields.fail(key, "expected " + std::string(expected) + ", got " + describe_node(*node));
    return value;
}

}  // namespace

bool Fields::boolean(std::string_view key, bool& out) {
    const auto* node =
        typed(*this, key, "true or false", [](const toml::node& n) { return n.as_boolean(); });
    if (node) out = **node;
    return node != nullptr;
}

bool Fields::string(std::string_view key, std::string& out) {
    const auto* node =
        typed(*this, key, "a string", [](const toml::node& n) { return n.as_string(); });
    if (node) out = **node;
    return node != nullptr;
}

bool Fields::table(std::string_view key, const toml::table*& out) {
    out = typed(*this, key, "a table", [](const toml::node& n) { return n.as_table(); });
    return out != nullptr;
}

bool Fields::array(std::string_view key, const toml::array*& out) {
    out = typed(*this, key, "an array", [](const toml::node& n) { return n.as_array(); });
    return out != nullptr;
}

void Fields::finish() {
    for (const auto& [key, node] : table_) {
        if (std::find(known_.begin(), known_.end(), key.str()) != known_.end()) continue;
        std::string names;
        for (auto it = known_.begin(); it != known_.end(); ++it) {
            if (std::find(known_.begin(), it, *it) != it) continue;
            if (!names.empty()) names += ", ";
            names += *it;
        }
        errors_.fail(key.source().begin.line ? key.source() : node.source(), path(key.str()),
                     "unknown key; expected one of " + names);
        return;
    }
}

bool array_integer(const toml::node& node, std::string_view path, std::int64_t min,
                   std::int64_t max, ProfileErrors& errors, std::int64_t& out) {
    auto i = node.as_integer();
    if (!i) {
        errors.fail(node.source(), path, "expected an integer, got " + describe_node(node));
        return false;
    }
    if (**i < min || **i > max) {
        errors.fail(node.source(), path,
                    "expected an integer from " + std::to_string(min) + " to " +
                        std::to_string(max) + ", got " + std::to_string(**i));
        return false;
    }
    out = **i;
    return true;
}

bool integer_pair(Fields& fields, std::string_view key, std::int64_t min, std::int64_t max,
                  std::int64_t& first, std::int64_t& last) {
    const toml::array* pair = nullptr;
    if (!fields.array(key, pair)) return false;
    if (pair->size() != 2) {
        fields.fail(key, "expected two integers [first, last], got " +
                             std::to_string(pair->size()) + " elements");
        return false;
    }
    const std::string path = fields.path(key);
    if (!array_integer(*pair->get(0), path + "[0]", min, max, fields.errors(), first)) return false;
    if (!array_integer(*pair->get(1), path + "[1]", min, max, fields.errors(), last)) return false;
    if (first > last) {
        fields.fail(key, "the first value " + std::to_string(first) + " is greater than the last " +
                             std::to_string(last));
        return false;
    }
    return true;
}

}  // namespace mblab::device
