// The examples the README and docs/load.md print, run with the binary under test and compared
// with what they show. "..." stands for what changes from run to run (ports, times, request
// counts): alone on a line it is any number of lines, within a line any text.
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "http_serve.hpp"
#include "support/temp_dir.hpp"

namespace mblab::test {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> lines_of(const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);)
        out.push_back(line);
    return out;
}

bool line_matches(std::string_view pattern, std::string_view line) {
    constexpr std::string_view kAny = "...";
    const auto first = pattern.find(kAny);
    if (first == pattern.npos) return pattern == line;
    if (!line.starts_with(pattern.substr(0, first))) return false;
    line.remove_prefix(first);
    pattern.remove_prefix(first + kAny.size());
    for (auto next = pattern.find(kAny); next != pattern.npos; next = pattern.find(kAny)) {
        const auto at = line.find(pattern.substr(0, next));
        if (at == line.npos) return false;
        line.remove_prefix(at + next);
        pattern.remove_prefix(next + kAny.size());
    }
    return line.ends_with(pattern);
}

bool lines_match(const std::vector<std::string>& want, std::size_t i,
                 const std::vector<std::string>& got, std::size_t j) {
    if (i == want.size()) return j == got.size();
    if (want[i] == "...") {
        for (std::size_t k = j; k <= got.size(); ++k)
            if (lines_match(want, i + 1, got, k)) return true;
        return false;
    }
    return j < got.size() && line_matches(want[i], got[j]) && lines_match(want, i + 1, got, j + 1);
}

// The lines a document shows after "$ COMMAND" up to the end of its block.
std::vector<std::string> shown_after(const std::string& doc, const std::string& command) {
    const auto text = file_text(fs::path(MBLAB_SOURCE_DIR) / doc);
    const auto start = text.find("\n$ " + command + "\n");
    if (start == std::string::npos) return {};
    const auto from = start + command.size() + 4;
    return lines_of(text.substr(from, text.find("\n```", from) - from));
}

TEST(DocExamples, TheReadmesFirstConformRunPrintsWhatItShows) {
    const auto shown = shown_after("README.md", "build/mblab conform");
    ASSERT_GT(shown.size(), 10U) << "no `$ build/mblab conform` example in README.md";
    TempDir dir;
    const auto ran = run_program(
        {"/bin/sh", "-c",
         "cd '" + dir.path().string() + "' && '" + std::string(MBLAB_BINARY) + "' conform"},
        std::chrono::seconds(120));
    EXPECT_EQ(ran.status, 0) << ran.err;
    EXPECT_TRUE(lines_match(shown, 0, lines_of(ran.out), 0))
        << "README.md shows:\n"
        << ::testing::PrintToString(shown) << "\nthe run printed:\n"
        << ran.out;
}

TEST(DocExamples, TheLoadHeaderCountsTheProtocolTestsAsShown) {
    const auto shown = file_text(fs::path(MBLAB_SOURCE_DIR) / "docs/load.md");
    const std::string line =
        "  protocol tests: 13 cases from policy-2.1 (... exchanges), one connection (or line) "
        "per node";
    ASSERT_NE(shown.find("\n" + line + "\n"), std::string::npos);
    ChildProcess serve(serve_argv({}));
    const auto target = modbus_target(serve);
    ASSERT_FALSE(target.empty());
    const auto ran = run_mblab({"load", target, "--registers", "65536", "--duration", "1s"});
    const auto got = lines_of(ran.out);
    ASSERT_GT(got.size(), 1U) << ran.err;
    EXPECT_TRUE(line_matches(line, got[1])) << got[1];
}

TEST(DocExamples, TheInstrumentProfileAnswersTheAddressTheReadmeSays) {
    const auto readme = file_text(fs::path(MBLAB_SOURCE_DIR) / "README.md");
    EXPECT_NE(readme.find("serial address 1, of the 1..95 its manual allows"), std::string::npos);
    ChildProcess serve(
        {MBLAB_BINARY, "serve", "rs485-instrument", "--listen", "rtu+tcp://127.0.0.1:0"});
    const auto line = serve.read_stdout_line(10s);
    ASSERT_TRUE(line);
    EXPECT_NE(line->find(", address 1 (0 is a broadcast; other addresses are not answered)"),
              std::string::npos)
        << *line;
}

TEST(DocExamples, DotsMatchWhatChanges) {
    EXPECT_TRUE(line_matches("in ... s, ... requests", "in 2.20 s, 914 requests"));
    EXPECT_FALSE(line_matches("in ... s, ... requests", "in 2.20 s, 914 answers"));
    EXPECT_TRUE(lines_match({"a", "...", "b"}, 0, {"a", "x", "y", "b"}, 0));
    EXPECT_TRUE(lines_match({"a", "...", "b"}, 0, {"a", "b"}, 0));
    EXPECT_FALSE(lines_match({"a", "b"}, 0, {"a", "x", "b"}, 0));
}

}  // namespace
}  // namespace mblab::test
