#pragma once

#include <string>
#include <string_view>

// The pieces every HTML page of mblab shares: escaping, and one self-contained page with its
// style and script inline, so a report opens from a USB stick with no network.
namespace mblab::web {

// `text` safe inside an element or a double-quoted attribute: & < > " ' escaped (as
// conformance::xml_escape does).
std::string html_escape(std::string_view text);

// A whole document: `title` in <title> and the page's CSS and JS around `body` (already HTML).
// The script filters elements marked as cases (class "case", data-verdict, data-id) by the
// checkboxes of class "verdict-filter" and the text box #search, counts them in #shown, and
// hides a <section class="suite"> none of whose cases is shown.
std::string html_page(std::string_view title, std::string_view body);

// "<tr><th>name</th><td>value</td></tr>", both escaped.
std::string field_row(std::string_view name, std::string_view value);

}  // namespace mblab::web
