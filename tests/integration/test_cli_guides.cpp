// What issue #14's "A CLI that guides" promises, checked as a user sees it: exit status and the
// exact lines printed.
#include <gtest/gtest.h>

#include "test_client_support.hpp"

namespace mblab::test {
namespace {

class CliGuides : public ClientCliTest {
  protected:
    void SetUp() override { start_reference_server(); }
};

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
    EXPECT_EQ(ran.status, 2);
    EXPECT_EQ(ran.out, "");
    EXPECT_EQ(ran.err,
              "mblab raw: PDU token 3 '123' has an odd number of hex digits: give each byte as 1 "
              "or 2 digits, or whole bytes run together (03 00 00 00 0A or 030000000A)\n");
    auto not_hex = mblab("raw", {"03", "zz"});
    EXPECT_EQ(not_hex.status, 2);
    EXPECT_EQ(not_hex.err,
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
    EXPECT_EQ(over.status, 2);
    EXPECT_EQ(over.err,
              "mblab read: --timeout: Value 660000 not in range 1 to 600000 (run 'mblab read "
              "--help' for usage)\n");
}

TEST(CliGuidesUsage, AnUnknownDurationUnitIsOneLine) {
    auto ran = run_mblab({"read", "tcp://127.0.0.1:1", "holding", "0", "--timeout", "1x"});
    EXPECT_EQ(ran.status, 2);
    EXPECT_EQ(ran.out, "");
    EXPECT_EQ(ran.err,
              "mblab read: --timeout: '1x' is not a duration: give e.g. 250ms, 1s, 1.5s or 2m (a "
              "number alone is milliseconds) (run 'mblab read --help' for usage)\n");
    auto half = run_mblab({"watch", "tcp://127.0.0.1:1", "holding", "0", "--interval", "1.5ms"});
    EXPECT_EQ(half.status, 2);
    EXPECT_EQ(half.err,
              "mblab watch: --interval: '1.5ms' is not a whole number of milliseconds (run 'mblab "
              "watch --help' for usage)\n");
    auto serve = run_mblab({"serve", "--idle-timeout", "5x"});
    EXPECT_EQ(serve.status, 2);
    EXPECT_EQ(serve.err,
              "mblab serve: --idle-timeout: '5x' is not a duration: give e.g. 250ms, 1s, 1.5s or "
              "2m (a number alone is seconds) (run 'mblab serve --help' for usage)\n");
    auto conform = run_mblab({"conform", "tcp://127.0.0.1:1", "--settle", "-1s"});
    EXPECT_EQ(conform.status, 2);
    EXPECT_EQ(conform.err,
              "mblab conform: --settle: '-1s' is not a duration: give e.g. 250ms, 1s, 1.5s or 2m "
              "(a number alone is milliseconds) (run 'mblab conform --help' for usage)\n");
}

TEST(CliGuidesUsage, AMistypedCommandGetsTheNearestOne) {
    auto ran = run_mblab({"confrom"});
    EXPECT_EQ(ran.status, 2);
    EXPECT_EQ(ran.out, "");
    EXPECT_EQ(ran.err, "mblab: unknown command 'confrom'; did you mean 'conform'?\n");
    auto read = run_mblab({"raed", "tcp://127.0.0.1:1", "holding", "0"});
    EXPECT_EQ(read.status, 2);
    EXPECT_EQ(read.err, "mblab: unknown command 'raed'; did you mean 'read'?\n");
}

TEST(CliGuidesUsage, AMistypedOptionGetsTheNearestOfItsCommand) {
    auto ran = run_mblab({"read", "tcp://127.0.0.1:1", "holding", "0", "--timout", "5"});
    EXPECT_EQ(ran.status, 2);
    EXPECT_EQ(ran.out, "");
    EXPECT_EQ(ran.err,
              "mblab read: unknown option --timout; did you mean --timeout? (run 'mblab read "
              "--help' for usage)\n");
    auto serve = run_mblab({"serve", "--idle-timout=3"});
    EXPECT_EQ(serve.status, 2);
    EXPECT_EQ(serve.err,
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
    EXPECT_NE(overview.out.find("Run 'mblab help COMMAND'"), std::string::npos);
    auto unknown = run_mblab({"help", "confrom"});
    EXPECT_EQ(unknown.status, 2);
    EXPECT_EQ(unknown.err, "mblab: unknown command 'confrom'; did you mean 'conform'?\n");
}

}  // namespace
}  // namespace mblab::test
