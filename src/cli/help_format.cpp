#include "cli/help_format.hpp"

#include <regex>
#include <vector>

namespace mblab::cli {

namespace {

std::vector<std::string> split_checks(const std::string& text) {
    // ':' splits the type from the checks, but a set's members may hold one ({a:b}).
    std::vector<std::string> parts{""};
    int depth = 0;
    for (const char c : text) {
        if (c == '{' || c == '[') ++depth;
        if (c == '}' || c == ']') --depth;
        if (c == ':' && depth == 0) {
            parts.emplace_back();
        } else {
            parts.back() += c;
        }
    }
    return parts;
}

}  // namespace

std::string value_words(const std::string& cli11_type) {
    const auto parts = split_checks(cli11_type);
    std::string words = parts.front();
    // A number is a number to the user, whatever its C++ type.
    if (words == "INT" || words == "UINT") words = "N";
    if (words == "FLOAT") words = "NUMBER";
    static const std::regex range(
        R"((?:INT|UINT|FLOAT|NUMBER|POSITIVE|NONNEGATIVE)? ?in \[(-?[0-9.e+]+) - (-?[0-9.e+]+)\])");
    for (std::size_t i = 1; i < parts.size(); ++i) {
        const auto& check = parts[i];
        std::smatch match;
        if (check == "FILE" || check == "PATH(existing)" || check == "FILE(existing)") {
            words = "FILE";
        } else if (check == "DIR" || check == "DIR(existing)") {
            words = "DIR";
        } else if (check.size() > 2 && check.front() == '{' && check.back() == '}') {
            auto members = check.substr(1, check.size() - 2);
            for (auto& c : members)
                if (c == ',') c = '|';
            words = members;
        } else if (std::regex_match(check, match, range) && words != "DURATION") {
            // A duration's range is in its bare unit, which the help text names.
            words = match[1].str() + ".." + match[2].str();
        } else if (check == "NONNEGATIVE" && words != "DURATION") {
            words = "N";
        }
    }
    return words;
}

std::string HelpFormatter::make_option_opts(const CLI::Option* option) const {
    if (!option->get_option_text().empty() || option->get_type_size() == 0) {
        return CLI::Formatter::make_option_opts(option);
    }
    std::string out;
    if (!option->get_type_name().empty()) out += " " + value_words(option->get_type_name());
    if (!option->get_default_str().empty()) out += "=" + option->get_default_str();
    if (option->get_expected_max() == CLI::detail::expected_max_vector_size) {
        out += " ...";
    } else if (option->get_expected_min() > 1) {
        out += " x " + std::to_string(option->get_expected());
    }
    if (option->get_required()) out += " " + get_label("REQUIRED");
    // Needs and excludes are said in the options' own texts.
    return out;
}

}  // namespace mblab::cli
