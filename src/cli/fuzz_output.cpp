#include "cli/fuzz_output.hpp"

#include <fmt/core.h>

#include "cli/commands.hpp"
#include "conformance/reports.hpp"
#include "robustness/fuzz_report.hpp"
#include "robustness/reproducer.hpp"

namespace mblab::cli {

namespace rb = mblab::robustness;
namespace conf = mblab::conformance;

namespace {

int write_failed(const std::string& message) {
    fmt::print(stderr, "mblab fuzz: {}\n", message);
    return kExitUsage;
}

}  // namespace

int write_fuzz_outputs(const rb::FuzzResult& result, const client::Target& target,
                       const FuzzOutputs& outputs, const conf::Capture& capture,
                       const conf::Provenance& provenance) {
    const auto framing = client::framing_of(target);
    const bool line = framing != client::Framing::Mbap;
    fmt::print("{}", rb::summary_text(result));
    std::string failed;
    if (result.finding) {
        const auto& f = *result.finding;
        const std::string comment = fmt::format(
            "mblab fuzz {} --seed {}\n{}: {} (case {})\nthe device {}\n{}\nreplay: "
            "mblab fuzz {} --replay {}",
            target.name, result.seed, rb::class_name(f.kind), f.case_name, f.case_number, f.reason,
            f.minimise_note, target.name, outputs.reproducer);
        if (!conf::write_text_file(outputs.reproducer, rb::reproducer_text(f.reproducer, comment),
                                   failed))
            return write_failed(failed);
        const auto capture_path = outputs.reproducer + ".pcapng";
        const bool written =
            line ? conf::write_line_pcap(capture_path, rb::reproducer_capture(f.reproducer, "", 0),
                                         framing, provenance, failed)
                 : conf::write_pcap(
                       capture_path,
                       rb::reproducer_capture(f.reproducer, target.tcp->host, target.tcp->port),
                       provenance, failed);
        if (!written) return write_failed(failed);
        fmt::print("reproducer written to {} (and {})\n", outputs.reproducer, capture_path);
    }
    if (!outputs.json.empty() &&
        !conf::write_text_file(outputs.json, rb::json_report(result, provenance), failed))
        return write_failed(failed);
    if (!outputs.junit.empty() &&
        !conf::write_text_file(outputs.junit, rb::junit_report(result, provenance), failed))
        return write_failed(failed);
    if (!outputs.pcap.empty() &&
        !conf::write_capture(outputs.pcap, capture.events(), framing, provenance, failed))
        return write_failed(failed);
    if (!outputs.pcap.empty() && capture.dropped_bytes() > 0) {
        fmt::print(
            "{} holds the run's last frames: the first {} byte(s) were let go to bound "
            "memory\n",
            outputs.pcap, capture.dropped_bytes());
    }
    return result.finding ? kExitFailed : kExitOk;
}

}  // namespace mblab::cli
