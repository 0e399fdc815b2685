#pragma once

#include <string_view>

// GET / of `mblab serve --http`: one page, its style (/dashboard.css) and script
// (/dashboard.js), nothing fetched from elsewhere, over the REST API and the event stream
// (docs/http.md).
namespace mblab::web {

std::string_view dashboard_page();
std::string_view dashboard_style();
std::string_view dashboard_script();

}  // namespace mblab::web
