#include "cli/fuzz_output.hpp"

#include <fmt/core.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <system_error>

#include "cli/commands.hpp"
#include "cli/report_files.hpp"
#include "conformance/reports.hpp"
#include "robustness/fuzz_report.hpp"
#include "robustness/reproducer.hpp"
#include "support/json_document.hpp"

namespace mblab::cli {

namespace rb = mblab::robustness;
namespace conf = mblab::conformance;

namespace {

int write_failed(const std::string& message) {
    fmt::print(stderr, "mblab fuzz: {}\n", message);
    return kExitUsage;
}

// The n-th finding's reproducer (from 1): --reproducer FILE for the first, FILE-n.hex (or
// FILE-n) for the others; finding-n.hex in the report directory without it.
std::optional<std::string> reproducer_path(const std::string& given, std::size_t n, ReportDir& dir,
                                           std::string& error) {
    if (given.empty()) {
        const auto made = dir.make(error);
        if (!made) return std::nullopt;
        return fmt::format("{}/finding-{}.hex", *made, n);
    }
    if (n == 1) return given;
    if (given.ends_with(".hex"))
        return fmt::format("{}-{}.hex", given.substr(0, given.size() - 4), n);
    return fmt::format("{}-{}", given, n);
}

}  // namespace

ReportDir::ReportDir(std::string given) : given_(std::move(given)) {}

std::optional<std::string> ReportDir::make(std::string& error) {
    if (!made_.empty()) return made_;
    std::string path = given_;
    const char* state = std::getenv("XDG_STATE_HOME");
    if (path.empty() && state != nullptr && state[0] == '/') {
        // A name of the time and the process: two runs in the same second still differ.
        const auto now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
        std::tm utc{};
        ::gmtime_r(&now, &utc);
        char stamp[32];
        std::strftime(stamp, sizeof stamp, "%Y%m%dT%H%M%SZ", &utc);
        path = fmt::format("{}/mblab/fuzz/{}-{}", state, stamp, ::getpid());
    }
    if (!path.empty()) {
        std::error_code failed;
        std::filesystem::create_directories(path, failed);
        if (failed) {
            error = fmt::format("{}: {}", path, failed.message());
            return std::nullopt;
        }
        made_ = path;
        return made_;
    }
    const char* tmp = std::getenv("TMPDIR");
    std::string pattern =
        fmt::format("{}/mblab-fuzz-XXXXXX", tmp != nullptr && tmp[0] == '/' ? tmp : "/tmp");
    if (::mkdtemp(pattern.data()) == nullptr) {
        error = fmt::format("{}: cannot make the report directory", pattern);
        return std::nullopt;
    }
    made_ = pattern;
    return made_;
}

int write_fuzz_outputs(const rb::FuzzResult& result, const client::Target& target,
                       const FuzzOutputs& outputs, ReportDir& dir, const conf::Capture& capture,
                       const conf::Provenance& provenance) {
    const auto framing = client::framing_of(target);
    const bool line = framing != client::Framing::Mbap;
    fmt::print(outputs.console, "{}{}", rb::summary_text(result), outputs.monitor_text);
    std::string failed;
    for (std::size_t n = 1; n <= result.findings.size(); ++n) {
        const auto& f = result.findings[n - 1];
        const auto path = reproducer_path(outputs.files.reproducer, n, dir, failed);
        if (!path) return write_failed(failed);
        const std::string comment = fmt::format(
            "mblab fuzz {} --seed {}\n{}: {} (case {})\nthe device {}\n{}\nreplay: "
            "mblab fuzz {} --replay {}",
            target.name, result.seed, rb::class_name(f.kind), f.case_name, f.case_number, f.reason,
            f.minimise_note, target.name, *path);
        if (!conf::write_text_file(*path, rb::reproducer_text(f.reproducer, comment), failed))
            return write_failed(failed);
        const auto capture_path = *path + ".pcapng";
        const bool written =
            line ? conf::write_line_pcap(capture_path, rb::reproducer_capture(f.reproducer, "", 0),
                                         framing, provenance, failed)
                 : conf::write_pcap(
                       capture_path,
                       rb::reproducer_capture(f.reproducer, target.tcp->host, target.tcp->port),
                       provenance, failed);
        if (!written) return write_failed(failed);
        fmt::print(outputs.console, "reproducer written to {} (and {})\n", *path, capture_path);
    }
    auto json = rb::json_report(result, provenance);
    if (outputs.monitor) {
        auto document = nlohmann::json::parse(json);
        document["monitor"] = *outputs.monitor;
        json = json_document(document) + "\n";
    }
    if (!outputs.files.json.empty() && !ReportFiles::write(outputs.files.json, json, failed))
        return write_failed(failed);
    // The report directory holds the JSON report beside the findings it explains.
    if (!outputs.monitor_html.empty()) {
        if (!dir.make(failed)) return write_failed(failed);
        const auto path = dir.made() + "/monitor.html";
        if (!conf::write_text_file(path, outputs.monitor_html, failed)) return write_failed(failed);
        fmt::print(outputs.console, "monitor's chart written to {}\n", path);
    }
    if (dir.given() || !dir.made().empty()) {
        if (!dir.make(failed)) return write_failed(failed);
        const auto path = dir.made() + "/report.json";
        if (!conf::write_text_file(path, json, failed)) return write_failed(failed);
        fmt::print(outputs.console, "report directory: {}\n", dir.made());
    }
    if (!outputs.files.junit.empty() &&
        !ReportFiles::write(
            outputs.files.junit,
            rb::junit_report(result, provenance,
                             outputs.monitor_junit ? &*outputs.monitor_junit : nullptr),
            failed))
        return write_failed(failed);
    if (!outputs.files.pcap.empty() &&
        !conf::write_capture(outputs.files.pcap, capture.events(), framing, provenance, failed))
        return write_failed(failed);
    if (!outputs.files.pcap.empty() && capture.dropped_bytes() > 0) {
        fmt::print(
            "{} holds the run's last frames: the first {} byte(s) were let go to bound "
            "memory\n",
            outputs.files.pcap, capture.dropped_bytes());
    }
    return result.findings.empty() && outputs.monitor_passed ? kExitOk : kExitFailed;
}

}  // namespace mblab::cli
