// What a user reads cites public documents: no help text, listing or report names the project's
// private notes ("seed 000", PROTOCOL.md, DESIGN.md), and neither do the shipped files a user
// reads (src/ strings, catalogue/, profiles/, docs/, README.md). docs/references.md lists what
// is cited instead.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "support/temp_path.hpp"
#include "test_client_support.hpp"

namespace mblab::test {
namespace {

using ::testing::HasSubstr;

// "seed 000", "seed001", "Seed 0003", PROTOCOL.md, DESIGN.md: the acceptance check of issue 30.
const std::regex& private_citation() {
    static const std::regex pattern("seed ?0{2,3}[0-9]|protocol\\.md|design\\.md",
                                    std::regex::icase);
    return pattern;
}

// The first line of `text` that cites a private note, or "" when none does.
std::string first_private_citation(const std::string& text) {
    std::istringstream lines(text);
    for (std::string line; std::getline(lines, line);) {
        if (std::regex_search(line, private_citation())) return line;
    }
    return "";
}

std::string slurp(const std::filesystem::path& path) {
    std::ifstream file(path);
    std::stringstream text;
    text << file.rdbuf();
    return text.str();
}

TEST(Citations, ThePatternCatchesWhatItIsFor) {
    EXPECT_NE(first_private_citation("ok\n(seed 000 7.3.1)\n"), "");
    EXPECT_NE(first_private_citation("profile instrument-seed001"), "");
    EXPECT_NE(first_private_citation("see PROTOCOL.md bad input 6"), "");
    EXPECT_EQ(first_private_citation("(CTP 7.3.1)\n--seed N  random seed of the mutations\n"), "");
}

TEST(Citations, NoHelpTextCitesAPrivateNote) {
    std::vector<std::vector<std::string>> helps = {{"--help"}};
    for (const char* command :
         {"conform", "conform-client", "serve", "load", "read", "write", "diag", "devid", "raw",
          "watch", "pki", "fuzz", "profile", "scan"}) {
        helps.push_back({command, "--help"});
    }
    helps.push_back({"profile", "import-csv", "--help"});
    for (const auto& args : helps) {
        const Ran ran = run_mblab(args);
        EXPECT_EQ(ran.status, 0) << args.front() << ran.err;
        EXPECT_EQ(first_private_citation(ran.out + ran.err), "") << "mblab " << args.front();
    }
}

TEST(Citations, TheCatalogueListingCitesSectionsAndNamesTheDocuments) {
    const Ran ran = run_mblab({"conform", "--list"});
    EXPECT_EQ(ran.status, 0) << ran.err;
    EXPECT_EQ(first_private_citation(ran.out), "");
    EXPECT_THAT(ran.out, HasSubstr("Function 0x01 read coils  (CTP 7.3.1)\n"));
    EXPECT_THAT(ran.out, HasSubstr("\nsources (docs/references.md):\n"));
    EXPECT_THAT(ran.out,
                HasSubstr("\n  CTP     Conformance Test Policy for the Modbus/TCP Conformance "
                          "Test Laboratory, version 2.1"));
    EXPECT_THAT(ran.out,
                HasSubstr("\n  APP     Modbus Application Protocol Specification V1.1b3  "
                          "https://modbus.org/docs/Modbus_Application_Protocol_V1_1b3.pdf\n"));
}

// The instrument serves no coils: the policy's 7.3.1 fails, and says which section requires the
// function; every report of that run cites documents, none a private note.
TEST(Citations, ReportsCiteDocumentsAndAMissingFunctionNamesTheSectionRequiringIt) {
    const std::string junit = temp_path("citations.xml");
    const std::string html = temp_path("citations.html");
    const std::string json = temp_path("citations.json");
    const Ran ran =
        run_mblab({"conform", "--profile", "rs485-instrument", "--suite", "policy-2.1", "--case",
                   "7.3.1", "--case", "7.5.1", "--junit", junit, "--html", html, "--json", json});
    EXPECT_EQ(ran.status, 1) << ran.out << ran.err;
    EXPECT_THAT(ran.out, HasSubstr("exception 01 (illegal function) where data was expected: "
                                   "the device does not serve function 01, which CTP 7.3.1 "
                                   "requires"));
    for (const auto& [name, text] :
         {std::pair{"console", ran.out + ran.err}, std::pair{"junit", slurp(junit)},
          std::pair{"html", slurp(html)}, std::pair{"json", slurp(json)}}) {
        EXPECT_FALSE(text.empty()) << name;
        EXPECT_EQ(first_private_citation(text), "") << name;
    }
    EXPECT_THAT(slurp(junit),
                HasSubstr("cites Conformance Test Policy for the Modbus/TCP Conformance "
                          "Test Laboratory, version 2.1 (University of Michigan), 7.3.1\n"));
    EXPECT_THAT(slurp(html),
                HasSubstr("<a href=\"https://modbus.org\" title=\"Conformance Test Policy "
                          "for the Modbus/TCP Conformance Test Laboratory, version 2.1 "
                          "(University of Michigan), 7.3.1\">CTP 7.3.1</a>"));
}

// The files a user reads, shipped or installed: the same check over the source tree.
TEST(Citations, NoShippedFileCitesAPrivateNote) {
    namespace fs = std::filesystem;
    const fs::path root = MBLAB_SOURCE_DIR;
    std::vector<fs::path> files = {root / "README.md"};
    for (const char* dir : {"src", "catalogue", "docs", "profiles"}) {
        for (const auto& entry : fs::recursive_directory_iterator(root / dir)) {
            if (entry.is_regular_file()) files.push_back(entry.path());
        }
    }
    ASSERT_GT(files.size(), 100U);
    for (const auto& file : files)
        EXPECT_EQ(first_private_citation(slurp(file)), "") << file;
}

}  // namespace
}  // namespace mblab::test
