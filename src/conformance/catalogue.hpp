#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "conformance/dut.hpp"
#include "conformance/pattern.hpp"
#include "protocol/result.hpp"

// A suite of conformance cases as loaded from catalogue/*.toml (docs/catalogue.md).
namespace mblab::conformance {

struct Alternative {
    Pattern pattern;
    std::string remark;  // empty for the preferred answer
};

struct Step {
    Pattern request;
    std::vector<std::size_t> split;  // the request is written in pieces cut at these offsets
    std::chrono::milliseconds split_delay{20};
    std::vector<Alternative> expect;  // first is preferred; empty when silence is expected
    std::optional<std::chrono::milliseconds> silence;  // the device must say nothing this long
    std::optional<std::string> accept_close;    // a close by the device passes, with this remark
    std::optional<std::string> accept_silence;  // no answer before the timeout passes, ditto
    std::optional<std::chrono::milliseconds> timeout;
    std::uint32_t line = 0;
};

struct Case {
    std::string id;
    std::string source;  // "CTP 7.3.1", "APP 6.11; CVE-2019-14462": docs/references.md
    std::string title;
    std::string procedure;  // empty for request/expect cases
    std::map<std::string, std::int64_t> params;
    std::vector<Step> steps;
    bool pipeline = false;           // every step's request in one write, answers read after
    bool isolated = false;           // runs on a connection of its own, closed afterwards
    bool unsupported_is_na = false;  // exception 01 to the first request makes the case N/A
    std::vector<Requirement> requirements;
    std::vector<std::string> depends_on;  // ids of cases in the same suite that must pass first
    std::uint32_t line = 0;
};

struct Suite {
    std::string name;
    std::string title;
    std::string source;
    std::string file;
    std::vector<Case> cases;
};

// Loads and checks a whole suite; the error is "file:line: reason".
protocol::Result<Suite, std::string> load_suite_file(const std::string& path);
protocol::Result<Suite, std::string> load_suite_text(std::string_view text,
                                                     const std::string& file_name);

// The shipped suites in `directory`, policy suites first, then by name.
std::vector<std::string> shipped_suite_files(const std::string& directory);

}  // namespace mblab::conformance
