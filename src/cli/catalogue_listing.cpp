#include "cli/catalogue_listing.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <set>
#include <string_view>

#include "conformance/references.hpp"

namespace mblab::cli {
namespace {

// The documents the listed sources cite, by tag: what "CTP 7.3.1" means without the docs at hand.
void print_cited_documents(const std::vector<conformance::Suite>& suites) {
    std::set<std::string_view> cited;
    for (const auto& suite : suites) {
        for (const auto& c : suite.cases) {
            for (const auto& citation : conformance::citations(c.source)) {
                if (const auto* reference = conformance::cited_reference(citation.text))
                    cited.insert(reference->tag);
            }
        }
    }
    if (cited.empty()) return;
    fmt::print("sources (docs/references.md):\n");
    for (const auto& reference : conformance::references()) {
        if (cited.count(reference.tag))
            fmt::print("  {:<6}  {}  {}\n", reference.tag, reference.title, reference.url);
    }
}

}  // namespace

void print_catalogue(const std::vector<conformance::Suite>& suites) {
    for (const auto& suite : suites) {
        fmt::print("{} ({}){}\n", suite.name, suite.file,
                   suite.title.empty() ? "" : ": " + suite.title);
        std::size_t width = 0;
        for (const auto& c : suite.cases)
            width = std::max(width, c.id.size());
        for (const auto& c : suite.cases) {
            std::string kind = c.procedure.empty() ? "" : fmt::format(" [{}]", c.procedure);
            fmt::print("  {:<{}}  {}{}  ({})\n", c.id, width, c.title, kind, c.source);
        }
    }
    print_cited_documents(suites);
}

}  // namespace mblab::cli
