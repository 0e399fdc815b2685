#include <fmt/core.h>

#include <cstdio>
#include <memory>

#include "conformance/evidence_text.hpp"
#include "conformance/reports.hpp"

namespace mblab::conformance {

namespace {

// Escapes for XML attributes and text alike; control characters other than tab and newline are
// not allowed in XML 1.0 and become spaces.
std::string xml(std::string_view text) {
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

std::string seconds(std::chrono::microseconds elapsed) {
    return fmt::format("{:.6f}", static_cast<double>(elapsed.count()) / 1e6);
}

std::string testcase(const std::string& suite, const CaseResult& c) {
    const auto& outcome = c.outcome;
    std::string out = fmt::format("    <testcase classname=\"{}\" name=\"{}\" time=\"{}\"",
                                  xml(suite), xml(c.id + " " + c.title), seconds(c.elapsed));
    if (c.interrupted)
        return out + ">\n      <skipped message=\"interrupted\"/>\n    </testcase>\n";
    switch (outcome.verdict) {
        case Verdict::Pass:
            if (outcome.reason.empty()) return out + "/>\n";
            return out + fmt::format(">\n      <system-out>{}</system-out>\n    </testcase>\n",
                                     xml(outcome.reason));
        case Verdict::Fail: {
            std::string body = fmt::format("{} ({})\n", c.source, outcome.reason);
            for (const auto& exchange : outcome.evidence) {
                for (const auto& line : evidence_lines(exchange))
                    body += line + "\n";
            }
            return out + fmt::format(
                             ">\n      <failure message=\"{}\" type=\"FAIL\">{}</failure>\n"
                             "    </testcase>\n",
                             xml(outcome.reason), xml(body));
        }
        case Verdict::NotApplicable:
        case Verdict::NotRun:
            return out + fmt::format(">\n      <skipped message=\"{}: {}\"/>\n    </testcase>\n",
                                     verdict_label(outcome.verdict), xml(outcome.reason));
    }
    return out + "/>\n";
}

}  // namespace

std::string junit_report(const RunResult& result) {
    const Counts total = result.counts();
    std::string out = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
    out += fmt::format(
        "<testsuites name=\"mblab conform {}\" tests=\"{}\" failures=\"{}\" errors=\"0\" "
        "skipped=\"{}\" time=\"{}\">\n",
        xml(result.target), total.total(), total.failed, total.not_applicable + total.not_run,
        seconds(result.elapsed));
    for (const auto& suite : result.suites) {
        const Counts counts = count(suite);
        std::chrono::microseconds elapsed{0};
        for (const auto& c : suite.cases)
            elapsed += c.elapsed;
        out += fmt::format(
            "  <testsuite name=\"{}\" tests=\"{}\" failures=\"{}\" errors=\"0\" skipped=\"{}\" "
            "time=\"{}\">\n",
            xml(suite.name), counts.total(), counts.failed, counts.not_applicable + counts.not_run,
            seconds(elapsed));
        for (const auto& c : suite.cases)
            out += testcase(suite.name, c);
        out += "  </testsuite>\n";
    }
    out += "</testsuites>\n";
    return out;
}

bool write_text_file(const std::string& path, const std::string& text, std::string& error) {
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "wb"),
                                                         &std::fclose);
    if (!file || std::fwrite(text.data(), 1, text.size(), file.get()) != text.size()) {
        error = fmt::format("cannot write {}", path);
        return false;
    }
    return true;
}

}  // namespace mblab::conformance
