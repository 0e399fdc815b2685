#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <string_view>

#include "cli/report_files.hpp"
#include "conformance/capture.hpp"
#include "conformance/provenance.hpp"
#include "conformance/reports.hpp"

// The report files of `mblab conform` (and of `mblab conform-client`, which checks them the same
// way and writes its own): --json, --junit, --html and --pcap, each checked before
// the run (a run must not end with "cannot write") and written after it. One text report may be
// `-`, standard output; the console report then goes to standard error.
namespace mblab::cli {

struct ConformReports : TextReports {
    std::string pcap;

    // The four options, their help naming what the run judges one by one (`item`: "case",
    // "scenario").
    void add_to(CLI::App& command, std::string_view item);
    bool wanted() const { return TextReports::wanted() || !pcap.empty(); }
    // False with `error` when a file cannot be written.
    bool check(ReportFiles& files, std::string& error) const;
    // The capture is laid out for `framing`: TCP packets for Modbus/TCP, a line's frames else.
    bool write(const conformance::RunResult& result, const conformance::Provenance& provenance,
               const conformance::Capture& capture, client::Framing framing, ReportFiles& files,
               std::string& error) const;
};

}  // namespace mblab::cli
