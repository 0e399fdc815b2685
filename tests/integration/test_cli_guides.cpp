// What issue #14's "A CLI that guides" promises, checked as a user sees it: exit status and the
// exact lines printed.
#include <fmt/core.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <csignal>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>

#include "test_client_support.hpp"

namespace mblab::test {
namespace {

using ::testing::HasSubstr;

using CliGuides = ReferenceCliTest;

// One hex digit is one byte, so `03 0 0 0 1` is the five bytes it reads as.
TEST_F(CliGuides, RawTakesASingleDigitAsOneByte) {
    auto ran = mblab("raw", {"03", "0", "0", "0", "1"});
    EXPECT_EQ(ran.status, 0) << ran.err;
    EXPECT_EQ(ran.out.substr(0, ran.out.find('\n')), "request  03 00 00 00 01");
    auto runs = mblab("raw", {"030000", "0x00:01"});
    EXPECT_EQ(runs.status, 0) << runs.err;
    EXPECT_EQ(runs.out.substr(0, runs.out.find('\n')), "request  03 00 00 00 01");
}

// An odd run of digits is neither a byte nor whole bytes: refused before anything is sent.
TEST_F(CliGuides, RawRefusesAnOddRunOfDigits) {
    auto ran = mblab("raw", {"03", "0", "123", "1"});
    EXPECT_EQ(ran.out, "");
    expect_failed(
        ran, 2,
        "mblab raw: PDU token 3 '123' has an odd number of hex digits: give each byte as 1 "
        "or 2 digits, or whole bytes run together (03 00 00 00 0A or 030000000A)\n");
    auto not_hex = mblab("raw", {"03", "zz"});
    expect_failed(not_hex, 2,
                  "mblab raw: 'zz' is not hex: give the PDU as hex bytes, e.g. 03 00 00 00 "
                  "0A\n");
}

// Durations take a unit wherever a duration is asked for; a bare number keeps the option's unit.
TEST_F(CliGuides, DurationsTakeUnits) {
    for (const char* timeout : {"1s", "250ms", "1.5s", "2m", "1000"}) {
        auto ran = mblab("read", {"holding", "0", "--timeout", timeout});
        EXPECT_EQ(ran.status, 0) << timeout << ": " << ran.err;
    }
    auto watch = mblab("watch", {"holding", "0", "--count", "2", "--interval", "0.01s"});
    EXPECT_EQ(watch.status, 0) << watch.err;
    // The unit is converted into the option's own before its limits are checked: 11m is
    // 660000 ms, over --timeout's 600000.
    auto over = mblab("read", {"holding", "0", "--timeout", "11m"});
    expect_failed(over, 2,
                  "mblab read: --timeout: Value 660000 not in range 1 to 600000 (run 'mblab read "
                  "--help' for usage)\n");
}

TEST(CliGuidesUsage, AnUnknownDurationUnitIsOneLine) {
    expect_usage(
        {"read", "tcp://127.0.0.1:1", "holding", "0", "--timeout", "1x"},
        "mblab read: --timeout: '1x' is not a duration: give e.g. 250ms, 1s, 1.5s or 2m (a "
        "number alone is milliseconds) (run 'mblab read --help' for usage)\n");
    expect_usage(
        {"watch", "tcp://127.0.0.1:1", "holding", "0", "--interval", "1.5ms"},
        "mblab watch: --interval: '1.5ms' is not a whole number of milliseconds (run 'mblab "
        "watch --help' for usage)\n");
    expect_usage(
        {"serve", "--idle-timeout", "5x"},
        "mblab serve: --idle-timeout: '5x' is not a duration: give e.g. 250ms, 1s, 1.5s or "
        "2m (a number alone is seconds) (run 'mblab serve --help' for usage)\n");
    expect_usage(
        {"conform", "tcp://127.0.0.1:1", "--settle", "-1s"},
        "mblab conform: --settle: '-1s' is not a duration: give e.g. 250ms, 1s, 1.5s or 2m "
        "(a number alone is milliseconds) (run 'mblab conform --help' for usage)\n");
}

TEST(CliGuidesUsage, AMistypedCommandGetsTheNearestOne) {
    expect_usage({"confrom"}, "mblab: unknown command 'confrom'; did you mean 'conform'?\n");
    expect_usage({"raed", "tcp://127.0.0.1:1", "holding", "0"},
                 "mblab: unknown command 'raed'; did you mean 'read'?\n");
}

TEST(CliGuidesUsage, AMistypedOptionGetsTheNearestOfItsCommand) {
    expect_usage({"read", "tcp://127.0.0.1:1", "holding", "0", "--timout", "5"},
                 "mblab read: unknown option --timout; did you mean --timeout? (run 'mblab read "
                 "--help' for usage)\n");
    expect_usage({"serve", "--idle-timout=3"},
                 "mblab serve: unknown option --idle-timout; did you mean --idle-timeout? (run "
                 "'mblab serve --help' for usage)\n");
}

// `mblab help CMD` prints what `mblab CMD --help` prints; `mblab help` the overview.
TEST(CliGuidesUsage, HelpCommandPrintsTheCommandsHelp) {
    for (const char* command : {"read", "raw", "serve", "conform", "load"}) {
        auto help = run_mblab({"help", command});
        auto flag = run_mblab({command, "--help"});
        EXPECT_EQ(help.status, 0) << command;
        EXPECT_EQ(help.out, flag.out) << command;
        EXPECT_NE(help.out.find(std::string("Usage: mblab ") + command), std::string::npos);
    }
    auto overview = run_mblab({"help"});
    EXPECT_EQ(overview.status, 0);
    EXPECT_EQ(overview.out, run_mblab({"--help"}).out);
    EXPECT_THAT(overview.out, HasSubstr("Run 'mblab help COMMAND'"));
    expect_usage({"help", "confrom"},
                 "mblab: unknown command 'confrom'; did you mean 'conform'?\n");
}

const std::regex kIsoTime(R"(\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d\.\d{3}Z)");

std::vector<std::string> lines_of(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);)
        lines.push_back(line);
    return lines;
}

// The table line of one value: what `read` prints after its header.
std::string first_row(const Ran& ran) {
    const auto lines = lines_of(ran.out);
    return lines.size() > 1 ? lines[1] : "";
}

// Manuals number from 1 and in Modicon references; each way names the same register.
TEST_F(CliGuides, AddressesTakeModiconReferencesAndBaseOne) {
    ASSERT_EQ(mblab("write", {"registers", "10", "7", "8"}).status, 0);
    const std::string expected = "10 (0x000A)  0x0007  7";
    for (std::vector<std::string> args : {std::vector<std::string>{"holding", "10"},
                                          {"holding", "4x00011"},
                                          {"holding", "4x0011"},
                                          {"holding", "400011"},
                                          {"holding", "11", "--base", "1"},
                                          {"holding", "4x00011", "--base", "1"}}) {
        auto ran = mblab("read", args);
        EXPECT_EQ(ran.status, 0) << args[1] << ": " << ran.err;
        EXPECT_EQ(first_row(ran), expected) << args[1];
    }
    // The other tables: coils in the 6-digit form, since 0x is hex.
    ASSERT_EQ(mblab("write", {"coil", "000003", "on"}).status, 0);
    EXPECT_EQ(first_row(mblab("read", {"coils", "2"})), "2 (0x0002)  1    on");
    EXPECT_EQ(first_row(mblab("read", {"coils", "3", "--base", "1"})), "2 (0x0002)  1    on");
    EXPECT_EQ(first_row(mblab("read", {"input", "3x00001"})),
              first_row(mblab("read", {"input", "0"})));
    EXPECT_EQ(first_row(mblab("read", {"discretes", "1x00001"})),
              first_row(mblab("read", {"discretes", "0"})));
    auto masked = mblab("write", {"mask", "12", "0", "0x00FF", "--base", "1"});
    EXPECT_EQ(masked.out, "masked register 11 (0x000B): and 0x0000, or 0x00FF\n");
}

TEST(CliGuidesUsage, AddressUsageErrorsAreOneLine) {
    expect_usage({"read", "tcp://127.0.0.1:1", "holding", "0", "--base", "1"},
                 "mblab read: ADDR 0 with --base 1: 1-based addresses start at 1\n");
    expect_usage({"read", "tcp://127.0.0.1:1", "holding", "300001"},
                 "mblab read: ADDR 300001 is a reference to input registers (3x), not to holding "
                 "registers (4x)\n");
    expect_usage({"write", "tcp://127.0.0.1:1", "coil", "4x00001", "1"},
                 "mblab write: ADDR 4x00001 is a reference to holding registers (4x), not to coils "
                 "(0x)\n");
    auto rw = run_mblab({"write", "tcp://127.0.0.1:1", "readwrite", "400001", "1", "300001", "5"});
    EXPECT_EQ(rw.err,
              "mblab write: WRITE_ADDR 300001 is a reference to input registers (3x), not to "
              "holding registers (4x)\n");
    auto base = run_mblab({"read", "tcp://127.0.0.1:1", "holding", "0", "--base", "2"});
    EXPECT_EQ(base.status, 2);
    auto over = run_mblab({"read", "tcp://127.0.0.1:1", "holding", "4x65537"});
    EXPECT_EQ(over.err, "mblab read: ADDR 4x65537: a 4x reference is from 4x00001 to 4x65536\n");
}

TEST(CliGuidesUsage, ClientHelpSaysAddressesAreZeroBased) {
    for (const char* command : {"read", "write", "watch"}) {
        auto help = run_mblab({command, "--help"});
        EXPECT_THAT(help.out, HasSubstr("0-based PDU offset")) << command;
        EXPECT_THAT(help.out, HasSubstr("--base")) << command;
        EXPECT_THAT(help.out, HasSubstr("4x00001")) << command;
    }
}

// A device with holes (profiles/access-ranges.toml): 8 discrete inputs, holding 0..29, 100..109.
class CliGuidesSmallDevice : public ClientCliTest {
  protected:
    void SetUp() override {
        auto loaded =
            device::load_profile(std::string(MBLAB_SOURCE_DIR) + "/profiles/access-ranges.toml");
        ASSERT_TRUE(loaded) << loaded.error();
        device_ = std::move(loaded.value());
        start_server(*device_);
    }
};

TEST_F(CliGuidesSmallDevice, ExceptionTwoAtAOneBasedLookingAddressGetsAHint) {
    auto modicon = mblab("read", {"holding", "40001"});
    EXPECT_EQ(modicon.status, 1);
    EXPECT_EQ(modicon.out, "");
    EXPECT_EQ(modicon.err,
              "mblab read: exception 02 illegal data address: 0x9C41 is not on this device; 40001 "
              "looks like a Modicon reference: try 4x00001 or --base 1 with 1\n");
    // One past the last that answers: the device answers the same read one lower.
    auto past = mblab("read", {"discretes", "8"});
    EXPECT_EQ(past.status, 1);
    EXPECT_EQ(past.err,
              "mblab read: exception 02 illegal data address: 0x0008 is not on this device; 7 "
              "(0x0007) answers: addresses are 0-based PDU offsets, so if 8 is 1-based try 7 or "
              "--base 1 with 8\n");
    // A hole with nothing readable below it gets no guess.
    auto hole = mblab("read", {"holding", "50"});
    EXPECT_EQ(hole.err,
              "mblab read: exception 02 illegal data address: 0x0032 is not on this device\n");
    auto write = mblab("write", {"register", "40001", "1"});
    EXPECT_EQ(write.status, 1);
    EXPECT_THAT(write.err,
                HasSubstr("; 40001 looks like a Modicon reference: try 4x00001 or --base 1 "
                          "with 1\n"));
    auto json = mblab("read", {"holding", "40001", "--json"});
    auto document = nlohmann::json::parse(json.out);
    EXPECT_EQ(document["status"], 1);
    EXPECT_NE(document["error"]["message"].get<std::string>().find("try 4x00001"),
              std::string::npos);
}

// A failed poll is a line of its own in either format.
TEST_F(CliGuidesSmallDevice, WatchStreamsFailedPolls) {
    auto ndjson = mblab("watch", {"holding", "50", "--count", "1", "--format", "ndjson"});
    EXPECT_EQ(ndjson.status, 1);
    auto line = nlohmann::json::parse(ndjson.out);
    EXPECT_EQ(line["ok"], false);
    EXPECT_EQ(line["error"]["kind"], "exception");
    auto csv = mblab("watch", {"holding", "50", "2", "--count", "1", "--format", "csv"});
    EXPECT_EQ(csv.status, 1);
    const auto lines = lines_of(csv.out);
    ASSERT_EQ(lines.size(), 2U);
    EXPECT_EQ(lines[1].substr(lines[1].find(',')),
              ",1,exception 02 illegal data address: 0x0032..0x0033 are not all on this device,,");
}

TEST_F(CliGuides, WatchStreamsCsv) {
    ASSERT_EQ(mblab("write", {"registers", "20", "1", "2", "3"}).status, 0);
    auto ran = mblab(
        "watch", {"holding", "20", "3", "--count", "3", "--interval", "10ms", "--format", "csv"});
    EXPECT_EQ(ran.status, 0) << ran.err;
    const auto lines = lines_of(ran.out);
    ASSERT_EQ(lines.size(), 4U) << ran.out;
    EXPECT_EQ(lines[0], "time,poll,error,20,21,22");
    for (std::size_t i = 1; i < lines.size(); ++i) {
        const auto comma = lines[i].find(',');
        EXPECT_TRUE(std::regex_match(lines[i].substr(0, comma), kIsoTime)) << lines[i];
        EXPECT_EQ(lines[i].substr(comma), fmt::format(",{},,1,2,3", i));
    }
    // The tally goes to stderr, so stdout is only CSV.
    EXPECT_EQ(ran.err,
              "mblab watch: 3 polls: 3 answered, 0 timeouts, 0 exceptions, 0 other errors\n");
    auto f32 =
        mblab("watch", {"holding", "20", "2", "--type", "f32", "--count", "1", "--format", "csv"});
    EXPECT_EQ(lines_of(f32.out).at(0), "time,poll,error,20,22");
}

TEST_F(CliGuides, WatchStreamsNdjson) {
    auto ran = mblab(
        "watch", {"coils", "0", "2", "--count", "2", "--interval", "10ms", "--format", "ndjson"});
    EXPECT_EQ(ran.status, 0) << ran.err;
    const auto lines = lines_of(ran.out);
    ASSERT_EQ(lines.size(), 2U) << ran.out;
    for (std::size_t i = 0; i < lines.size(); ++i) {
        auto line = nlohmann::json::parse(lines[i]);
        EXPECT_TRUE(std::regex_match(line["time"].get<std::string>(), kIsoTime));
        EXPECT_EQ(line["poll"], i + 1);
        EXPECT_EQ(line["ok"], true);
        EXPECT_EQ(line["values"].size(), 2U);
    }
}

// Each poll's line is written when it is read, not when the watch ends.
TEST_F(CliGuides, WatchFlushesEveryPoll) {
    ChildProcess child({MBLAB_BINARY, "watch", target(), "holding", "0", "--interval", "100ms",
                        "--format", "ndjson"});
    auto first = child.read_stdout_line(std::chrono::seconds(10));
    ASSERT_TRUE(first);
    EXPECT_EQ(nlohmann::json::parse(*first)["poll"], 1);
    auto second = child.read_stdout_line(std::chrono::seconds(10));
    ASSERT_TRUE(second);
    EXPECT_EQ(nlohmann::json::parse(*second)["poll"], 2);
    child.signal(SIGINT);
    EXPECT_EQ(child.wait_exit(std::chrono::seconds(10)), 0);
}

TEST(CliGuidesUsage, WatchFormatUsageErrors) {
    expect_usage(
        {"watch", "tcp://127.0.0.1:1", "fifo", "0x04DE", "--format", "csv"},
        "mblab watch: --format csv takes coils, discretes, holding or input, whose columns "
        "are known before the first answer: use --format ndjson\n");
    auto both =
        run_mblab({"watch", "tcp://127.0.0.1:1", "holding", "0", "--format", "ndjson", "--json"});
    EXPECT_EQ(both.status, 2);
}

// On a terminal (script(1) gives it one) a value that changed is in reverse video; NO_COLOR
// and a pipe get none.
TEST_F(CliGuides, WatchHighlightsChangesOnATerminal) {
    // event-log's message count goes up with every request, so it changes on every poll.
    const std::string watch =
        fmt::format("{} watch {} event-log --count 3 --interval 10ms", MBLAB_BINARY, target());
    if (::access("/usr/bin/script", X_OK) != 0) GTEST_SKIP() << "no script(1)";
    auto colour = run_program({"/usr/bin/script", "-qec", "env -u NO_COLOR " + watch, "/dev/null"});
    EXPECT_EQ(colour.status, 0) << colour.err;
    EXPECT_THAT(colour.out, HasSubstr("\x1b[7m"));
    auto plain = run_program({"/usr/bin/script", "-qec", "env NO_COLOR=1 " + watch, "/dev/null"});
    EXPECT_EQ(plain.status, 0) << plain.err;
    EXPECT_EQ(plain.out.find("\x1b[7m"), std::string::npos) << plain.out;
    auto piped = mblab("watch", {"event-log", "--count", "3", "--interval", "10ms"});
    EXPECT_EQ(piped.out.find('\x1b'), std::string::npos);
}

// A mistyped suite or profile name gets the nearest shipped one suggested.
TEST(CliGuidesUsage, AMistypedSuiteOrProfileGetsTheNearestOne) {
    auto suite = run_mblab({"conform", "--suite", "polcy-2.1"});
    EXPECT_EQ(suite.status, 2);
    EXPECT_THAT(suite.err, HasSubstr("mblab conform: no suite named 'polcy-2.1'; did you mean "
                                     "'policy-2.1'? (shipped suites: "));
    auto profile = run_mblab({"serve", "refrence"});
    EXPECT_EQ(profile.status, 2);
    EXPECT_THAT(profile.err,
                HasSubstr("mblab serve: no profile file or shipped profile named 'refrence'; "
                          "did you mean 'reference'? (shipped: "));
    auto unrelated = run_mblab({"conform", "--suite", "zzzz"});
    EXPECT_EQ(unrelated.err.find("did you mean"), std::string::npos) << unrelated.err;
}

// conform shows verdicts in colour on a terminal only, and never with NO_COLOR.
TEST(CliGuidesColour, ConformColoursVerdictsOnATerminalOnly) {
    if (::access("/usr/bin/script", X_OK) != 0) GTEST_SKIP() << "no script(1)";
    const std::string conform =
        fmt::format("{} conform --suite mbap --case mbap.1 --case mbap.9", MBLAB_BINARY);
    auto colour =
        run_program({"/usr/bin/script", "-qec", "env -u NO_COLOR " + conform, "/dev/null"});
    EXPECT_EQ(colour.status, 0) << colour.out;
    EXPECT_THAT(colour.out, HasSubstr("  \x1b[32mPASS\x1b[0m     mbap.1 "));
    auto plain = run_program({"/usr/bin/script", "-qec", "env NO_COLOR=1 " + conform, "/dev/null"});
    EXPECT_EQ(plain.status, 0) << plain.out;
    EXPECT_EQ(plain.out.find("\x1b[3"), std::string::npos) << plain.out;
    auto piped = run_mblab({"conform", "--suite", "mbap", "--case", "mbap.1"});
    EXPECT_EQ(piped.out.find('\x1b'), std::string::npos) << piped.out;
    EXPECT_THAT(piped.out, HasSubstr("  PASS     mbap.1 "));
}

// With --json a usage error is a document on stdout too; the stderr line stays.
TEST(CliGuidesUsage, JsonUsageErrorsAreDocuments) {
    const std::vector<std::string> args = {"read", "tcp://127.0.0.1:1", "holding",
                                           "0",    "--timout",          "5"};
    auto text = run_mblab(args);
    auto with_json = args;
    with_json.push_back("--json");
    auto json = run_mblab(with_json);
    EXPECT_EQ(text.status, 2);
    EXPECT_EQ(text.out, "");
    expect_failed(json, 2, text.err);
    auto document = nlohmann::json::parse(json.out);
    EXPECT_EQ(document["command"], "read");
    EXPECT_EQ(document["ok"], false);
    EXPECT_EQ(document["status"], 2);
    EXPECT_EQ(document["error"]["kind"], "usage");
    EXPECT_EQ(document["error"]["message"],
              "unknown option --timout; did you mean --timeout? (run 'mblab read --help' for "
              "usage)");
    // Every client command, and errors found after parsing too.
    for (std::vector<std::string> command :
         {std::vector<std::string>{"write", "tcp://127.0.0.1:1", "--unit", "300"},
          {"diag", "--json"},
          {"devid", "tcp://127.0.0.1:1", "--decode", "all"},
          {"raw", "tcp://127.0.0.1:1", "--retries", "x"},
          {"watch", "tcp://127.0.0.1:1", "holding", "0", "--interval", "1x"},
          {"read", "tcp://127.0.0.1:1", "holding", "0", "--base", "1"}}) {
        command.push_back("--json");
        auto ran = run_mblab(command);
        EXPECT_EQ(ran.status, 2) << command[0];
        auto doc = nlohmann::json::parse(ran.out);
        EXPECT_EQ(doc["command"], command[0]);
        EXPECT_EQ(doc["status"], 2) << command[0];
        EXPECT_EQ(doc["error"]["kind"], "usage") << command[0];
    }
    // After --, --json is a value, not the flag.
    auto late = run_mblab({"write", "tcp://127.0.0.1:1", "register", "--", "1", "--json", "x"});
    EXPECT_EQ(late.status, 2);
    EXPECT_EQ(late.out, "");
}

// -- ends the options, so a value that starts with - is a value.
TEST_F(CliGuides, DoubleDashLetsValuesBeNegative) {
    auto five = mblab("write", {"register", "7", "--type", "i16", "--", "-5"});
    EXPECT_EQ(five.status, 0) << five.err;
    EXPECT_EQ(first_row(mblab("read", {"holding", "7", "--type", "i16"})),
              "7 (0x0007)  0xFFFB  -5");
    // CLI11 already takes -DIGIT... as a value (no option is a digit); -.5 and -inf need --.
    auto bare = mblab("write", {"register", "7", "--type", "i16", "-6"});
    EXPECT_EQ(bare.status, 0) << bare.err;
    auto floats = mblab("write", {"registers", "8", "--type", "f32", "--", "-.5", "-inf"});
    EXPECT_EQ(floats.status, 0) << floats.err;
    auto read = mblab("read", {"holding", "8", "2", "--type", "f32"});
    EXPECT_THAT(read.out, HasSubstr("-0.5"));
    EXPECT_THAT(read.out, HasSubstr("-inf"));
    auto without = mblab("write", {"registers", "8", "--type", "f32", "-.5"});
    EXPECT_EQ(without.out, "");
    expect_failed(without, 2,
                  "mblab write: -.5 was taken for an option: put -- before negative values, after "
                  "the options (... -- -.5) (run 'mblab write --help' for usage)\n");
}

// Every command's help has its summary, an example and its exit statuses.
TEST(CliGuidesUsage, EveryHelpHasAnExampleAndExitStatuses) {
    for (const char* command : {"conform", "conform-client", "serve", "read", "write", "diag",
                                "devid", "raw", "watch", "load", "pki"}) {
        auto help = run_mblab({command, "--help"});
        EXPECT_EQ(help.status, 0) << command;
        EXPECT_THAT(help.out, HasSubstr("Exit status")) << command;
        EXPECT_NE(help.out.find(std::string("Example: mblab ") + command), std::string::npos)
            << command;
    }
}

}  // namespace
}  // namespace mblab::test
