#pragma once

#include <string_view>

// GET / of `mblab serve --http`: one self-contained page (inline CSS and script, nothing
// fetched from elsewhere) over the REST API and the event stream (docs/http.md).
namespace mblab::web {

std::string_view dashboard_page();

}  // namespace mblab::web
