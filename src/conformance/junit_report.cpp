#include <fmt/core.h>
#include <unistd.h>

#include <cstdio>
#include <memory>

#include "conformance/evidence_text.hpp"
#include "conformance/references.hpp"
#include "conformance/reports.hpp"

namespace mblab::conformance {

namespace {

std::string seconds(std::chrono::microseconds elapsed) {
    return fmt::format("{:.6f}", static_cast<double>(elapsed.count()) / 1e6);
}

std::string testcase(const std::string& suite, const CaseResult& c) {
    const auto& outcome = c.outcome;
    std::string out =
        fmt::format("    <testcase classname=\"{}\" name=\"{}\" time=\"{}\"", xml_escape(suite),
                    xml_escape(c.id + " " + c.title), seconds(c.elapsed));
    if (c.interrupted)
        return out + ">\n      <skipped message=\"interrupted\"/>\n    </testcase>\n";
    switch (outcome.verdict) {
        case Verdict::Pass:
            if (outcome.reason.empty()) return out + "/>\n";
            return out + fmt::format(">\n      <system-out>{}</system-out>\n    </testcase>\n",
                                     xml_escape(outcome.reason));
        case Verdict::Fail: {
            std::string body = fmt::format("{} ({})\n", c.source, outcome.reason);
            // A CI page has no docs/references.md beside it: the documents by name.
            if (const auto full = cited_in_full(c.source); full != c.source)
                body += fmt::format("cites {}\n", full);
            for (const auto& exchange : outcome.evidence) {
                for (const auto& line : evidence_lines(exchange))
                    body += line + "\n";
            }
            return out + fmt::format(
                             ">\n      <failure message=\"{}\" type=\"FAIL\">{}</failure>\n"
                             "    </testcase>\n",
                             xml_escape(outcome.reason), xml_escape(body));
        }
        case Verdict::NotApplicable:
        case Verdict::NotRun:
            return out + fmt::format(">\n      <skipped message=\"{}: {}\"/>\n    </testcase>\n",
                                     verdict_label(outcome.verdict), xml_escape(outcome.reason));
    }
    return out + "/>\n";
}

void property(std::string& out, std::string_view name, std::string_view value) {
    out += fmt::format("      <property name=\"{}\" value=\"{}\"/>\n", xml_escape(name),
                       xml_escape(value));
}

// junit-10 has <properties> in a <testsuite> only, not in <testsuites>, so each suite carries
// the run's provenance: a tool that reads one suite still sees where it came from.
std::string properties(const Provenance& provenance) {
    std::string out = "    <properties>\n";
    property(out, "mblab.version", provenance.version);
    property(out, "mblab.commit", provenance.commit);
    property(out, "run.started", provenance.started);
    property(out, "run.finished", provenance.finished);
    property(out, "run.command_line", shell_words(provenance.command_line));
    property(out, "dut.declared_by", provenance.declared_by);
    for (const auto& declaration : provenance.declarations) {
        property(out, "dut." + declaration.key, value_text(declaration));
        property(out, "dut." + declaration.key + ".source", declaration.source);
    }
    const DeviceIdentity& device = provenance.device;
    property(out, "device.identity", device.answered ? "answered" : "not answered");
    if (device.answered) {
        property(out, "device.vendor_name", device.vendor_name);
        property(out, "device.product_code", device.product_code);
        property(out, "device.revision", device.revision);
    } else {
        property(out, "device.identity.reason", device.reason);
    }
    return out + "    </properties>\n";
}

std::chrono::microseconds suite_time(const SuiteResult& suite) {
    std::chrono::microseconds elapsed{0};
    for (const auto& c : suite.cases)
        elapsed += c.elapsed;
    return elapsed;
}

// The counts of the <testcase> elements a suite shows: one N/A when it cannot apply at all.
Counts shown_counts(const SuiteResult& suite) {
    if (!suite_inapplicable(suite.name, suite.cases)) return count(suite);
    Counts one;
    one.not_applicable = 1;
    return one;
}

std::string junit_document(const RunResult& result, const std::string& suite_properties) {
    Counts total;
    for (const auto& suite : result.suites)
        total += shown_counts(suite);
    // The total is the sum of the suites' times, so the figures agree when a reader adds them
    // up; the run's wall time (which also holds connecting and settling between cases) is the
    // JSON report's. Whole microseconds, so the printed figures add up exactly.
    std::chrono::microseconds total_time{0};
    for (const auto& suite : result.suites)
        total_time += suite_time(suite);
    std::string out = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
    // junit-10 gives <testsuites> no `skipped`; each <testsuite> has it.
    out += fmt::format(
        "<testsuites name=\"mblab conform {}\" tests=\"{}\" failures=\"{}\" errors=\"0\" "
        "time=\"{}\">\n",
        xml_escape(result.target), total.total(), total.failed, seconds(total_time));
    for (const auto& suite : result.suites) {
        const auto inapplicable = suite_inapplicable(suite.name, suite.cases);
        const Counts counts = shown_counts(suite);
        out += fmt::format(
            "  <testsuite name=\"{}\" tests=\"{}\" failures=\"{}\" errors=\"0\" skipped=\"{}\" "
            "time=\"{}\">\n",
            xml_escape(suite.name), counts.total(), counts.failed,
            counts.not_applicable + counts.not_run, seconds(suite_time(suite)));
        out += suite_properties;
        if (inapplicable) {
            // One <testcase> says why the whole suite cannot apply, as the console's one line.
            out += fmt::format(
                "    <testcase classname=\"{}\" name=\"{}\" time=\"{}\">\n      <skipped "
                "message=\"{}: {}\"/>\n    </testcase>\n",
                xml_escape(suite.name), xml_escape(inapplicable->title), seconds(suite_time(suite)),
                verdict_label(Verdict::NotApplicable), xml_escape(inapplicable->reason));
        } else {
            for (const auto& c : suite.cases)
                out += testcase(suite.name, c);
        }
        out += "  </testsuite>\n";
    }
    out += "</testsuites>\n";
    return out;
}

}  // namespace

std::string junit_report(const RunResult& result, const Provenance& provenance) {
    return junit_document(result, properties(provenance));
}

std::string junit_report(const RunResult& result) {
    return junit_document(result, "");
}

std::string xml_escape(std::string_view text) {
    std::string out;
    out.reserve(text.size());
    for (char c : text) {
        switch (c) {
            case '&':
                out += "&amp;";
                break;
            case '<':
                out += "&lt;";
                break;
            case '>':
                out += "&gt;";
                break;
            case '"':
                out += "&quot;";
                break;
            case '\'':
                out += "&apos;";
                break;
            default:
                if (static_cast<unsigned char>(c) < 0x20 && c != '\n' && c != '\t') {
                    out += ' ';
                } else {
                    out += c;
                }
        }
    }
    return out;
}

bool write_text_file(const std::string& path, const std::string& text, std::string& error) {
    // Written beside it, then renamed over it: a run stopped half-way (a closed pipe, Ctrl-C)
    // leaves the earlier report whole, or none, never an empty or cut one.
    const std::string temporary = fmt::format("{}.{}.tmp", path, ::getpid());
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(temporary.c_str(), "wb"),
                                                         &std::fclose);
    const bool written =
        file && std::fwrite(text.data(), 1, text.size(), file.get()) == text.size();
    const bool closed = file && std::fclose(file.release()) == 0;
    if (!written || !closed || std::rename(temporary.c_str(), path.c_str()) != 0) {
        std::remove(temporary.c_str());
        error = fmt::format("cannot write {}", path);
        return false;
    }
    return true;
}

}  // namespace mblab::conformance
