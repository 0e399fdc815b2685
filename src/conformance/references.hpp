#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

// The public documents that case sources cite. A source is one or more citations separated by
// "; ", each starting with a document's short tag: "CTP 7.3.1", "APP 6.11, Figure 21 (...);
// CVE-2019-14462". docs/references.md is this table for readers; keep the two in step.
namespace mblab::conformance {

struct Reference {
    std::string_view tag;    // "CTP"
    std::string_view title;  // "Modbus/TCP Conformance Test Policy, version 2.1"
    std::string_view url;    // where to get it
};

// Every document a shipped source may cite, in the order docs/references.md lists them.
std::span<const Reference> references();

// The document whose tag starts `citation` ("CTP 7.3.1" -> CTP), or nullptr.
const Reference* cited_reference(std::string_view citation);

struct Citation {
    std::string text;   // as the source writes it: "CTP 7.3.1"
    std::string title;  // the document and the rest: "Modbus/TCP Conformance ..., 7.3.1"
    std::string url;    // the document (an RFC or CVE: its section or record); may be empty
};

// The citations of a source; a part without a known tag keeps its text as the title.
std::vector<Citation> citations(std::string_view source);

// The source with each tag written out as its document's title, for reports read without
// docs/references.md at hand (JUnit).
std::string cited_in_full(std::string_view source);

}  // namespace mblab::conformance
