#include "web/json_text.hpp"

#include <fmt/format.h>

#include "support/json_document.hpp"

namespace mblab::web {

namespace {

// The deepest nesting of arrays and objects in `text`, brackets inside strings not counted; it
// stops counting past `limit`, so the scan is one pass with no allocation.
int nesting(std::string_view text, int limit) {
    int depth = 0;
    int deepest = 0;
    bool in_string = false;
    bool escaped = false;
    for (const char c : text) {
        if (in_string) {
            if (escaped) {
                escaped = false;
            } else if (c == '\\') {
                escaped = true;
            } else if (c == '"') {
                in_string = false;
            }
            continue;
        }
        if (c == '"') {
            in_string = true;
        } else if (c == '[' || c == '{') {
            deepest = std::max(deepest, ++depth);
            if (deepest > limit) return deepest;
        } else if ((c == ']' || c == '}') && depth > 0) {
            --depth;
        }
    }
    return deepest;
}

}  // namespace

std::string json_text(const nlohmann::json& value) {
    return json_document(value, -1);
}

std::optional<nlohmann::json> parse_json_body(std::string_view body, std::string& error) {
    if (nesting(body, kMaxJsonDepth) > kMaxJsonDepth) {
        error =
            fmt::format("the body nests arrays or objects deeper than {} levels", kMaxJsonDepth);
        return std::nullopt;
    }
    auto parsed = nlohmann::json::parse(body, nullptr, false);
    if (parsed.is_discarded()) {
        error = "the body is not valid JSON";
        return std::nullopt;
    }
    return parsed;
}

}  // namespace mblab::web
