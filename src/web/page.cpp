#include "web/page.hpp"

#include <fmt/core.h>

#include "conformance/reports.hpp"

namespace mblab::web {

namespace {

constexpr std::string_view kStyle = R"(
body { font-family: system-ui, sans-serif; margin: 1.5em; color: #1b1b1b; background: #fff; }
h1 { font-size: 1.4em; } h2 { font-size: 1.15em; margin-top: 1.6em; }
table { border-collapse: collapse; margin: 0.5em 0; }
th, td { border: 1px solid #ccc; padding: 0.2em 0.6em; text-align: left; vertical-align: top; }
th { background: #f2f2f2; }
td.number { text-align: right; font-variant-numeric: tabular-nums; }
pre { margin: 0.3em 0; font-size: 0.9em; }
pre#plan { white-space: pre-wrap; }
table.cases { max-width: 100%; }
table.cases td:nth-child(4), table.cases td:nth-child(5) { overflow-wrap: anywhere; }
pre.evidence { white-space: pre-wrap; overflow-wrap: anywhere; }
mark.diff { background: #ffb3b3; color: #000; font-weight: bold; }
.banner { padding: 0.5em 0.8em; font-weight: bold; display: inline-block; }
.PASS { color: #126b12; } .FAIL { color: #b30000; } .NA, .NOTRUN, .INCOMPLETE { color: #8a6100; }
.banner.PASS { background: #dff3df; } .banner.FAIL { background: #fbdcdc; }
.banner.INCOMPLETE, .banner.NOTRUN { background: #fbf0d0; }
.controls { position: sticky; top: 0; background: #fff; padding: 0.5em 0; border-bottom: 1px solid #ccc; }
.controls label { margin-right: 1em; }
svg.histogram { background: #fafafa; border: 1px solid #ddd; font-size: 12px; }
svg.histogram .axis-title { font-weight: bold; }
table#nodes { max-width: 100%; }
table#nodes td:first-child { overflow-wrap: anywhere; }
svg.histogram rect.bar { fill: #3b6fb6; }
svg.histogram text { font-size: 10px; fill: #333; }
)";

// Plain JS (no library): shows the cases whose verdict is ticked and whose id holds the search
// text, and says how many are shown.
constexpr std::string_view kScript = R"(
(function () {
  var search = document.getElementById('search');
  var boxes = Array.prototype.slice.call(document.querySelectorAll('input.verdict-filter'));
  var cases = Array.prototype.slice.call(document.querySelectorAll('.case'));
  var shown = document.getElementById('shown');
  function apply() {
    var wanted = {};
    boxes.forEach(function (box) { wanted[box.value] = box.checked; });
    var text = search ? search.value.trim().toLowerCase() : '';
    var count = 0;
    cases.forEach(function (c) {
      var visible = wanted[c.dataset.verdict] !== false &&
                    c.dataset.id.toLowerCase().indexOf(text) !== -1;
      c.hidden = !visible;
      if (visible) count++;
    });
    // A suite with nothing left to show is hidden whole, header and all.
    document.querySelectorAll('section.suite').forEach(function (suite) {
      suite.hidden = !suite.querySelector('.case:not([hidden])');
    });
    if (shown) shown.textContent = count + ' of ' + cases.length + ' cases shown';
  }
  boxes.forEach(function (box) { box.addEventListener('change', apply); });
  if (search) search.addEventListener('input', apply);
  apply();
})();
)";

}  // namespace

std::string html_escape(std::string_view text) {
    // HTML takes what XML takes; one escaping for both report formats.
    return conformance::xml_escape(text);
}

std::string html_page(std::string_view title, std::string_view body) {
    return fmt::format(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
        "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
        "<title>{}</title>\n<style>{}</style>\n</head>\n<body>\n{}<script>{}</script>\n"
        "</body>\n</html>\n",
        html_escape(title), kStyle, body, kScript);
}

std::string field_row(std::string_view name, std::string_view value) {
    return fmt::format("<tr><th>{}</th><td>{}</td></tr>\n", html_escape(name), html_escape(value));
}

}  // namespace mblab::web
