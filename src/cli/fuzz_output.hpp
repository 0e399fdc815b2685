#pragma once

#include <cstdint>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "client/target.hpp"
#include "conformance/capture.hpp"
#include "conformance/provenance.hpp"
#include "robustness/fuzz_run.hpp"
#include "robustness/monitor_junit.hpp"

// What `mblab fuzz` leaves behind once a run is over: the summary on the console, each finding's
// reproducer (hex lines and a pcapng of its frames) in the report directory, the JSON and JUnit
// reports and the run's capture, where the command line asked for them.
namespace mblab::cli {

// Where findings go: `--report-dir DIR`, or a fresh directory under $XDG_STATE_HOME/mblab/fuzz
// (or, without it, a new mblab-fuzz-XXXXXX in $TMPDIR or /tmp), never the current directory. It
// is made when the first file is written to it: a run without a finding leaves nothing behind.
class ReportDir {
  public:
    explicit ReportDir(std::string given);
    // The directory, made if need be; nullopt with `error` set when it cannot be.
    std::optional<std::string> make(std::string& error);
    // "" until made.
    const std::string& made() const { return made_; }
    bool given() const { return !given_.empty(); }

  private:
    std::string given_;
    std::string made_;
};

// The files the command line names (--reproducer, --json, --junit, --pcap).
struct FuzzFiles {
    std::string reproducer;  // the first finding's hex lines when given; FILE.pcapng beside it
    std::string json;
    std::string junit;
    std::string pcap;
};

struct FuzzOutputs {
    // Standard error when a report takes standard output ("-").
    std::FILE* console = stdout;
    FuzzFiles files;
    // With --monitor: its phases and verdict, printed after the summary and added to the JSON
    // report as "monitor".
    std::string monitor_text = {};
    std::optional<nlohmann::json> monitor = {};
    std::string monitor_html = {};  // written to the report directory as monitor.html
    std::optional<robustness::JunitSuite> monitor_junit = {};  // a second suite in --junit
    bool monitor_passed = true;
};

// Prints the summary and writes the files; the command's exit status (2 when a file cannot be
// written, 1 for a finding or a monitor verdict other than PASS, 0 otherwise).
int write_fuzz_outputs(const robustness::FuzzResult& result, const client::Target& target,
                       const FuzzOutputs& outputs, ReportDir& dir,
                       const conformance::Capture& capture,
                       const conformance::Provenance& provenance);

}  // namespace mblab::cli
