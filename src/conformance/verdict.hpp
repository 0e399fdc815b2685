#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "client/link_types.hpp"
#include "conformance/dut.hpp"
#include "conformance/pattern.hpp"

// What a run found: a verdict per case, with the evidence for every failure.
namespace mblab::conformance {

enum class Verdict : std::uint8_t { Pass, Fail, NotApplicable, NotRun };

std::string_view verdict_label(Verdict verdict);  // "PASS", "FAIL", "N/A", "NOT RUN"

// One request and what came back, kept for failures.
struct Exchange {
    std::vector<std::uint8_t> sent;
    client::ReceiveStatus status = client::ReceiveStatus::Timeout;
    std::vector<std::uint8_t> received;
    std::string detail;             // why a connection closed or a frame was malformed
    std::size_t discarded = 0;      // bytes that came after `received`, counted but not kept
    std::size_t on_connection = 0;  // requests the connection had carried, this one included
    std::chrono::milliseconds waited{0};
    bool silence_expected = false;  // the device was to say nothing
    std::string expected;           // the expected pattern as text; empty for silence
    MatchResult match;              // against the closest expected pattern
    // How `sent` and `received` are laid out: the catalogue's notation (MBAP frames) while a case
    // is judged; a line's own framing once show_as_on_line (line_evidence.hpp) has run.
    client::Framing framing = client::Framing::Mbap;
};

// The verdict of a case, with a reason for every verdict that is not a plain PASS.
struct Outcome {
    Verdict verdict = Verdict::Pass;
    std::string reason;  // failure summary, N/A or NOT RUN cause, or a PASS remark
    std::vector<Exchange> evidence;
    // N/A for want of a declaration: the DUT key (the summary says what declaring it would run).
    std::string undeclared = {};
};

struct CaseResult {
    std::string id;
    std::string source;
    std::string title;
    Outcome outcome;
    std::chrono::microseconds elapsed{0};
    std::size_t requests = 0;
    bool interrupted = false;  // the run was stopped before this case (NOT RUN)
};

struct SuiteResult {
    std::string name;
    std::string title;
    std::string file;
    std::vector<CaseResult> cases;
};

struct Counts {
    std::size_t passed = 0;
    std::size_t failed = 0;
    std::size_t not_applicable = 0;
    std::size_t not_run = 0;
    std::size_t total() const { return passed + failed + not_applicable + not_run; }
    void add(Verdict verdict);
    Counts& operator+=(const Counts& other);
};

struct RunResult {
    std::string target;
    Dut dut;
    std::vector<SuiteResult> suites;
    std::chrono::microseconds elapsed{0};
    std::size_t requests = 0;
    bool interrupted = false;  // stopped early (SIGINT, SIGTERM); cases not reached are NOT RUN
    // Set when the run stopped because nothing ever answered (Engine::stop_if_unanswered): what
    // was tried, in one line; the cases not reached are NOT RUN.
    std::string unanswered;

    Counts counts() const;
    bool all_passed() const { return counts().failed == 0; }
};

Counts count(const SuiteResult& suite);

// A suite that cannot apply to the target (the security suite over tcp://): more than one case,
// every one N/A for one reason. The console, the HTML report and JUnit show it as one line, in
// these words: "all 12 cases of security" and the reason.
struct Inapplicable {
    std::string title;
    std::string reason;
};
// `cases` are the whole suite's; nullopt when the suite applies, even in part.
std::optional<Inapplicable> suite_inapplicable(std::string_view suite_name,
                                               std::span<const CaseResult> cases);

}  // namespace mblab::conformance
