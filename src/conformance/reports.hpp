#pragma once

#include <string>
#include <string_view>

#include "conformance/provenance.hpp"
#include "conformance/verdict.hpp"

// Machine-readable reports of a run.
namespace mblab::conformance {

// The whole run as JSON, with where it came from (docs/catalogue.md "Reports" describes the
// fields).
std::string json_report(const RunResult& result, const Provenance& provenance);
// Without the provenance, for `mblab load`, which borrows the report's shape for its evidence.
std::string json_report(const RunResult& result);

// JUnit XML as Jenkins and GitLab read it, valid against Jenkins' junit-10 schema
// (tests/junit-10.xsd): a <testsuite> per suite with the provenance as its <properties>, a
// <testcase> per case, <failure> for FAIL, <skipped> for N/A and NOT RUN.
std::string junit_report(const RunResult& result, const Provenance& provenance);
// Without <properties>, for `mblab load`'s report, which has no provenance yet.
std::string junit_report(const RunResult& result);

// `text` safe in XML (and HTML) attributes and text alike: & < > " ' escaped; control
// characters other than tab and newline are not allowed in XML 1.0 and become spaces.
std::string xml_escape(std::string_view text);

// Writes `text` to `path` whole or not at all (a temporary file renamed over it); false with
// `error` set when the file cannot be written.
bool write_text_file(const std::string& path, const std::string& text, std::string& error);

}  // namespace mblab::conformance
