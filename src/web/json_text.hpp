#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>

// JSON in and out of the HTTP side, safe for whatever a client sends: text that is not UTF-8 (a
// path of %FF) is written with U+FFFD in its place instead of throwing, and a body is parsed
// only when its nesting is shallow (a megabyte of '[' would otherwise cost tens of megabytes).
namespace mblab::web {

// Deep enough for every body the API takes (a fault rule nests three levels).
constexpr int kMaxJsonDepth = 32;

std::string json_text(const nlohmann::json& value);
// The body as JSON, or nullopt with a one-line `error` (not JSON, or nested too deep).
std::optional<nlohmann::json> parse_json_body(std::string_view body, std::string& error);

}  // namespace mblab::web
