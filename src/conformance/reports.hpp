#pragma once

#include <string>

#include "conformance/verdict.hpp"

// Machine-readable reports of a run.
namespace mblab::conformance {

// The whole run as JSON (docs/catalogue.md "Reports" describes the fields).
std::string json_report(const RunResult& result);

// JUnit XML as Jenkins and GitLab read it: a <testsuite> per suite, a <testcase> per case,
// <failure> for FAIL, <skipped> for N/A and NOT RUN.
std::string junit_report(const RunResult& result);

// Writes `text` to `path`; false with `error` set when the file cannot be written.
bool write_text_file(const std::string& path, const std::string& text, std::string& error);

}  // namespace mblab::conformance
