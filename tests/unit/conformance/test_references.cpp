// The table of cited documents: tags expand to titles and links, every shipped case cites
// documents of the table, and docs/references.md lists the same tags.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "conformance/catalogue.hpp"
#include "conformance/references.hpp"

namespace mblab::conformance {
namespace {

TEST(References, ATagBecomesItsDocumentWithTheSection) {
    const auto cited = citations("CTP 7.3.1");
    ASSERT_EQ(cited.size(), 1U);
    EXPECT_EQ(cited[0].text, "CTP 7.3.1");
    EXPECT_EQ(cited[0].title,
              "Conformance Test Policy for the Modbus/TCP Conformance Test Laboratory, version 2.1 "
              "(University of Michigan), 7.3.1");
    EXPECT_EQ(cited[0].url, "https://modbus.org");
}

TEST(References, SeveralCitationsAreSplitAtSemicolons) {
    const auto cited = citations("APP 6.11, Figure 21 (byte count); CVE-2019-14462");
    ASSERT_EQ(cited.size(), 2U);
    EXPECT_EQ(cited[0].title,
              "Modbus Application Protocol Specification V1.1b3, 6.11, Figure 21 (byte count)");
    EXPECT_EQ(cited[0].url, "https://modbus.org/docs/Modbus_Application_Protocol_V1_1b3.pdf");
    EXPECT_EQ(cited[1].text, "CVE-2019-14462");
    EXPECT_EQ(cited[1].url, "https://www.cve.org/CVERecord?id=CVE-2019-14462");
}

TEST(References, AnRfcLinksToItsSection) {
    const auto cited = citations("RFC 5246 7.2.1, RFC 8446 6.1");
    ASSERT_EQ(cited.size(), 1U);
    EXPECT_EQ(cited[0].url, "https://www.rfc-editor.org/rfc/rfc5246#section-7.2.1");
    EXPECT_EQ(citations("SEC R-60 (RFC 5746)")[0].url,
              "https://modbus.org/docs/MB-TCP-Security-v36_2021-07-30.pdf");
}

TEST(References, AnUnknownTagIsKeptAsWritten) {
    const auto cited = citations("my device manual 4.2");
    ASSERT_EQ(cited.size(), 1U);
    EXPECT_EQ(cited[0].title, "my device manual 4.2");
    EXPECT_EQ(cited[0].url, "");
    // A tag is a whole word: "APPENDIX" is not APP.
    EXPECT_EQ(cited_reference("APPENDIX A"), nullptr);
    EXPECT_EQ(cited_in_full("my device manual 4.2"), "my device manual 4.2");
}

TEST(References, InFullWritesEachTagOut) {
    EXPECT_EQ(cited_in_full("TCPG 4.4.2.2 (protocol id); APP 7"),
              "Modbus Messaging on TCP/IP Implementation Guide V1.0b, 4.4.2.2 (protocol id); "
              "Modbus Application Protocol Specification V1.1b3, 7");
}

TEST(References, EveryShippedCaseCitesDocumentsOfTheTable) {
    const auto files = shipped_suite_files(std::string(MBLAB_SOURCE_DIR) + "/catalogue");
    ASSERT_GE(files.size(), 7U);
    std::size_t cases = 0;
    for (const auto& file : files) {
        auto suite = load_suite_file(file);
        ASSERT_TRUE(suite.ok()) << suite.error();
        EXPECT_NE(cited_reference(suite->source), nullptr) << suite->name << ": " << suite->source;
        for (const auto& c : suite->cases) {
            ++cases;
            for (const auto& citation : citations(c.source)) {
                EXPECT_NE(cited_reference(citation.text), nullptr)
                    << suite->name << " " << c.id << ": " << citation.text;
            }
        }
    }
    EXPECT_GT(cases, 100U);
}

TEST(References, TheDocsPageListsEveryTag) {
    std::ifstream file(std::string(MBLAB_SOURCE_DIR) + "/docs/references.md");
    std::stringstream text;
    text << file.rdbuf();
    ASSERT_FALSE(text.str().empty());
    for (const auto& reference : references()) {
        const std::string row = "| `" + std::string(reference.tag);
        EXPECT_NE(text.str().find(row), std::string::npos) << reference.tag;
        EXPECT_NE(text.str().find(std::string(reference.url)), std::string::npos) << reference.tag;
    }
}

}  // namespace
}  // namespace mblab::conformance
