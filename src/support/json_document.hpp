#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace mblab {

// A document as JSON text. Text that is not UTF-8 (what a device or a client sent: an
// identification string, a client's raw output) is written with U+FFFD in its place: nlohmann's
// default is to throw, which lost whole reports.
inline std::string json_document(const nlohmann::json& value, int indent = 2) {
    return value.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace mblab
