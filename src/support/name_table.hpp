#pragma once

#include <cstddef>
#include <string_view>
#include <type_traits>

// The words an enum's values are shown with, one row per value: a value's name, label and
// meaning sit together in one row instead of one switch per word, so adding a value is one row.
namespace mblab {

// The row whose `value` is `value`, or nullptr. Rows are few (a dozen at most), so a scan is as
// fast as anything else and keeps the table in the order a reader expects.
template <class Row, std::size_t N, class Value>
constexpr const Row* row_of(const Row (&rows)[N], Value value) {
    for (const Row& row : rows) {
        if (row.value == value) return &row;
    }
    return nullptr;
}

// One word of the row whose `value` is `value` (the `column` member), or `unknown`.
template <class Row, std::size_t N, class Value, class Text>
constexpr Text word_of(const Row (&rows)[N], Value value, Text Row::*column,
                       std::type_identity_t<Text> unknown) {
    const Row* row = row_of(rows, value);
    return row != nullptr ? row->*column : unknown;
}

// `Text` is const char* where callers hand the name to C strings.
template <class Enum, class Text = std::string_view>
struct Named {
    Enum value;
    Text name;
};

template <class Enum, class Text, std::size_t N>
constexpr Text name_of(const Named<Enum, Text> (&names)[N], Enum value,
                       std::type_identity_t<Text> unknown) {
    return word_of(names, value, &Named<Enum, Text>::name, unknown);
}

}  // namespace mblab
