#pragma once

#include <string>
#include <string_view>
#include <vector>

// Options that take a comma-separated list ("quantity,pairwise", "register=5,period=100").
namespace mblab {

// The items of `text` between commas, empty ones left out.
inline std::vector<std::string> comma_items(std::string_view text) {
    std::vector<std::string> out;
    for (std::size_t from = 0; from <= text.size();) {
        auto end = text.find(',', from);
        if (end == std::string_view::npos) end = text.size();
        if (end > from) out.emplace_back(text.substr(from, end - from));
        from = end + 1;
    }
    return out;
}

}  // namespace mblab
