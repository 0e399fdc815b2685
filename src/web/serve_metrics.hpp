#pragma once

#include <string>

#include "web/device_api.hpp"

// GET /metrics of `mblab serve --http`: requests and exceptions per unit and function code, the
// answer time histogram, connections, and each unit's serial line counters (FC 08).
namespace mblab::web {

std::string serve_metrics(const ServeView& view);

}  // namespace mblab::web
