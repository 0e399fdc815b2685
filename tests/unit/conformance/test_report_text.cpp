// Text a device or a client sent, in the reports: bytes that are not UTF-8 must not stop a report
// from being written (nlohmann's JSON writer throws on them by default, and mblab then exited
// without a report).
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "conformance/reports.hpp"

namespace mblab::conformance {
namespace {

TEST(ReportText, AJsonReportCarriesTextThatIsNotUtf8WithAReplacementCharacter) {
    RunResult result;
    result.target = "tcp://127.0.0.1:1502";
    Provenance provenance;
    provenance.command_line = {"mblab", "conform", "tcp://127.0.0.1:1502"};
    provenance.device = {true, "M\xFCller", "P1", "1.0", ""};
    std::string text;
    ASSERT_NO_THROW(text = json_report(result, provenance));
    const auto report = nlohmann::json::parse(text);
    EXPECT_EQ(report["provenance"]["device_identity"]["vendor_name"], "M\xEF\xBF\xBDller");
}

}  // namespace
}  // namespace mblab::conformance
