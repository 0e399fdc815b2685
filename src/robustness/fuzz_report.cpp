#include "robustness/fuzz_report.hpp"

#include <fmt/core.h>

#include <nlohmann/json.hpp>

#include "client/hex_text.hpp"
#include "conformance/reports.hpp"
#include "robustness/iec62443_report.hpp"
#include "robustness/reproducer.hpp"
#include "support/json_document.hpp"

namespace mblab::robustness {

namespace {

std::string codes(const std::vector<std::uint8_t>& functions) {
    if (functions.empty()) return "none";
    return client::hex_bytes(functions);
}

// "holding registers 0-9, 100; coils 0-15", the tables with no range left out.
std::string ranges_text(const AnsweredRanges& ranges) {
    std::string out;
    for (std::size_t t = 0; t < kTableCount; ++t) {
        const auto table = static_cast<Table>(t);
        if (ranges.of(table).empty()) continue;
        out += fmt::format("{}{}", out.empty() ? "" : "; ", table_name(table));
        const char* separator = " ";
        for (const auto& r : ranges.of(table)) {
            out += r.first == r.last ? fmt::format("{}{}", separator, r.first)
                                     : fmt::format("{}{}-{}", separator, r.first, r.last);
            separator = ", ";
        }
    }
    return out;
}

nlohmann::json ranges_json(const AnsweredRanges& ranges) {
    nlohmann::json out = nlohmann::json::object();
    for (std::size_t t = 0; t < kTableCount; ++t) {
        const auto table = static_cast<Table>(t);
        nlohmann::json list = nlohmann::json::array();
        for (const auto& r : ranges.of(table))
            list.push_back({r.first, r.last});
        out[table_key(table)] = list;
    }
    return out;
}

std::string finding_comment(const Finding& finding) {
    return fmt::format("{}: {} (case {})\n{}\n{}", class_name(finding.kind), finding.case_name,
                       finding.case_number, finding.reason, finding.minimise_note);
}

std::string finding_text(const Finding& f) {
    std::string out =
        fmt::format("FINDING: the device {} (waited {} ms)\n", f.reason, f.waited.count());
    out += fmt::format("  case {}, {}: {}\n", f.case_number, class_name(f.kind), f.case_name);
    out += fmt::format("  {}\n", f.minimise_note);
    out += "  reproducer:\n";
    // A resource case's reproducer runs to thousands of lines: the file holds them all.
    constexpr std::size_t kShown = 20;
    constexpr std::size_t kLongest = 200;
    std::string text = reproducer_text(f.reproducer, "");
    std::size_t lines = 0;
    for (std::size_t from = 0; from < text.size(); ++lines) {
        const auto end = text.find('\n', from);
        if (lines < kShown) {
            const auto line = text.substr(from, end - from);
            out += "    " +
                   (line.size() > kLongest ? fmt::format("{} ... ({} characters)",
                                                         line.substr(0, kLongest), line.size())
                                           : line) +
                   "\n";
        }
        from = end + 1;
    }
    if (lines > kShown) out += fmt::format("    ... {} more step(s)\n", lines - kShown);
    return out;
}

nlohmann::json finding_json(const Finding& f) {
    nlohmann::json steps = nlohmann::json::array();
    for (const auto& step : f.reproducer) {
        steps.push_back({{"connection", step.connection},
                         {"hex", client::hex_bytes(step.bytes)},
                         {"pause_ms", step.pause.count()},
                         {"unread", step.unread},
                         {"vanish", step.vanish}});
    }
    return {{"class", class_name(f.kind)},
            {"requirement", requirement_of(f.kind)},
            {"case", f.case_name},
            {"case_number", f.case_number},
            {"reason", f.reason},
            {"waited_ms", f.waited.count()},
            {"minimised", f.minimised},
            {"minimise_note", f.minimise_note},
            {"frames_since_check", f.since_check.size()},
            {"reproducer", steps}};
}

// The first finding of `kind`, or null.
const Finding* finding_of(const FuzzResult& result, BadInput kind) {
    for (const auto& f : result.findings) {
        if (f.kind == kind) return &f;
    }
    return nullptr;
}

}  // namespace

std::string recon_text(const Recon& recon) {
    const std::string ranges =
        recon.ranges.empty() ? "" : fmt::format("  answered at: {}\n", ranges_text(recon.ranges));
    return fmt::format(
               "reconnaissance ({}): unit {}, serves {}; exception 01 for {}; silent for {}\n"
               "  liveness check: FC 03 register {}; largest FC 03 read {}; unit 0 {}, unit 255 "
               "{}\n",
               recon.source, recon.unit, codes(recon.served), codes(recon.not_served),
               codes(recon.silent), recon.check_address, recon.max_read,
               recon.answers_unit_0 ? "answered" : "not answered",
               recon.answers_unit_255 ? "answered" : "not answered") +
           ranges +
           (recon.killed_by ? fmt::format("  stopped after the probe of FC 0x{:02X}: the device "
                                          "no longer answers the read it answered before\n",
                                          recon.killed_by->function)
                            : "");
}

std::string summary_text(const FuzzResult& result) {
    std::string out =
        fmt::format("{} cases in {:.1f} s ({}), {} liveness checks, longest wait {} ms, seed {}\n",
                    result.cases, static_cast<double>(result.elapsed.count()) / 1000.0,
                    result.stopped_by, result.checks, result.longest_wait.count(), result.seed);
    for (std::size_t i = 0; i < kBadInputCount; ++i) {
        const auto& tally = result.classes[i];
        if (!tally.not_applicable.empty()) {
            out += fmt::format("  {:<17}   n/a {}\n", class_name(static_cast<BadInput>(i)),
                               tally.not_applicable);
            continue;
        }
        if (tally.run == 0 && tally.withheld == 0) continue;
        out += fmt::format("  {:<17} {:>5} run", class_name(static_cast<BadInput>(i)), tally.run);
        if (tally.withheld > 0)
            out += fmt::format(", {} withheld (writes not allowed)", tally.withheld);
        out += "\n";
    }
    if (result.one_connection_at_a_time) {
        out +=
            "the device serves one connection at a time: no connection was kept open "
            "across cases for the check\n";
    }
    if (result.ledger.floods > 0) {
        out += fmt::format(
            "flood writes read back: {} flood(s), {} writes acknowledged, the last one kept\n",
            result.ledger.floods, result.ledger.acknowledged);
    }
    if (result.ledger.unacknowledged > 0) {
        out += fmt::format(
            "flood writes: none acknowledged in {} flood(s) (refused or unanswered), nothing to "
            "read back\n",
            result.ledger.unacknowledged);
    }
    if (result.memory) {
        const auto& m = *result.memory;
        out += fmt::format(
            "device memory (pid {}): {:.1f} MiB resident at the start, {:.1f} MiB at the end, "
            "peak {:.1f} MiB\n",
            m.pid, static_cast<double>(m.start_kb) / 1024.0, static_cast<double>(m.end_kb) / 1024.0,
            static_cast<double>(m.peak_kb) / 1024.0);
    }
    if (result.findings.empty()) {
        out += "no finding: the device served every liveness check\n";
        return out;
    }
    if (result.findings.size() > 1)
        out += fmt::format("{} findings (--keep-going):\n", result.findings.size());
    for (const auto& f : result.findings)
        out += finding_text(f);
    return out;
}

std::string json_report(const FuzzResult& result, const conformance::Provenance& provenance) {
    nlohmann::json classes = nlohmann::json::array();
    for (std::size_t i = 0; i < kBadInputCount; ++i) {
        const auto kind = static_cast<BadInput>(i);
        classes.push_back({{"class", class_name(kind)},
                           {"expected", class_expectation(kind)},
                           {"run", result.classes[i].run},
                           {"withheld", result.classes[i].withheld},
                           {"not_applicable", result.classes[i].not_applicable},
                           {"finding", finding_of(result, kind) != nullptr}});
    }
    const auto& r = result.recon;
    nlohmann::json document = {
        {"tool", "mblab fuzz"},
        {"version", provenance.version},
        {"commit", provenance.commit},
        {"started", provenance.started},
        {"finished", provenance.finished},
        {"command_line", provenance.command_line},
        {"target", result.target},
        {"seed", result.seed},
        {"recon",
         {{"source", r.source},
          {"unit", r.unit},
          {"served", r.served},
          {"not_served", r.not_served},
          {"silent", r.silent},
          {"check_address", r.check_address},
          {"max_read", r.max_read},
          {"answers_unit_0", r.answers_unit_0},
          {"answers_unit_255", r.answers_unit_255},
          {"answered_ranges", ranges_json(r.ranges)}}},
        {"cases", result.cases},
        {"checks", result.checks},
        {"sends", result.sends},
        {"elapsed_ms", result.elapsed.count()},
        {"longest_wait_ms", result.longest_wait.count()},
        {"stopped_by", result.stopped_by},
        {"one_connection_at_a_time", result.one_connection_at_a_time},
        {"ledger",
         {{"floods_read_back", result.ledger.floods},
          {"acknowledged_writes", result.ledger.acknowledged},
          {"floods_without_acknowledged_writes", result.ledger.unacknowledged}}},
        {"classes", classes},
        {"verdict", result.findings.empty() ? "no finding" : "finding"},
    };
    if (result.memory) {
        document["device_memory_kb"] = {{"pid", result.memory->pid},
                                        {"start", result.memory->start_kb},
                                        {"end", result.memory->end_kb},
                                        {"peak", result.memory->peak_kb}};
    }
    nlohmann::json findings = nlohmann::json::array();
    for (const auto& f : result.findings)
        findings.push_back(finding_json(f));
    // "finding" is the first, as before --keep-going; "findings" has them all.
    if (!result.findings.empty()) document["finding"] = findings.front();
    document["findings"] = findings;
    return json_document(document) + "\n";
}

std::string junit_report(const FuzzResult& result, const conformance::Provenance& provenance,
                         const JunitSuite* suite) {
    using conformance::xml_escape;
    std::size_t skipped = 0;
    std::size_t failures = 0;
    for (std::size_t i = 0; i < kBadInputCount; ++i) {
        const bool failed = finding_of(result, static_cast<BadInput>(i)) != nullptr;
        failures += failed ? 1 : 0;
        skipped += result.classes[i].run == 0 && !failed ? 1 : 0;
    }
    const double seconds = static_cast<double>(result.elapsed.count()) / 1000.0;
    std::string out = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
    out += fmt::format(
        "<testsuites name=\"mblab fuzz {}\" tests=\"{}\" failures=\"{}\" "
        "time=\"{:.3f}\">\n",
        xml_escape(result.target), kBadInputCount + (suite ? suite->tests : 0),
        failures + (suite ? suite->failures : 0), seconds);
    out += fmt::format(
        "  <testsuite name=\"robustness\" tests=\"{}\" failures=\"{}\" errors=\"0\" "
        "skipped=\"{}\" time=\"{:.3f}\">\n",
        kBadInputCount, failures, skipped, seconds);
    out += "    <properties>\n";
    for (const auto& line : conformance::provenance_lines(provenance)) {
        const auto colon = line.find(": ");
        out += fmt::format("      <property name=\"{}\" value=\"{}\"/>\n",
                           xml_escape(line.substr(0, colon)),
                           xml_escape(colon == std::string::npos ? "" : line.substr(colon + 2)));
    }
    out += fmt::format("      <property name=\"seed\" value=\"{}\"/>\n", result.seed);
    out += "    </properties>\n";
    for (std::size_t i = 0; i < kBadInputCount; ++i) {
        const auto kind = static_cast<BadInput>(i);
        const auto& tally = result.classes[i];
        out += fmt::format("    <testcase classname=\"robustness\" name=\"{}\" time=\"0\">",
                           class_name(kind));
        if (const auto* found = finding_of(result, kind)) {
            const auto& f = *found;
            out += fmt::format(
                "\n      <failure message=\"{}\" type=\"finding\">{}</failure>\n    ",
                xml_escape(fmt::format("the device {} after: {}", f.reason, f.case_name)),
                xml_escape(reproducer_text(f.reproducer, finding_comment(f))));
        } else if (tally.run == 0) {
            const std::string_view why = !tally.not_applicable.empty() ? tally.not_applicable
                                         : tally.withheld > 0
                                             ? "every case would write outside the writable range"
                                             : "not reached within the budget";
            out += fmt::format("\n      <skipped message=\"{}\"/>\n    ", xml_escape(why));
        }
        out += "</testcase>\n";
    }
    out += "  </testsuite>\n";
    if (suite != nullptr) out += suite->xml;
    out += "</testsuites>\n";
    return out;
}

}  // namespace mblab::robustness
