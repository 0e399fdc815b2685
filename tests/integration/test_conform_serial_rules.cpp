// The serial suite [SER]: mblab's reference device passes it over RTU, ASCII and RTU over TCP,
// and slaves built wrong on purpose, each breaking one rule of the line on a pty pair, fail the
// case about that rule with a reason that names the fault.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "serial_test_support.hpp"
#include "support/temp_path.hpp"
#include "test_client_support.hpp"
#include "wrong_serial_slave.hpp"

namespace mblab::test {
namespace {

struct Verdict {
    std::string verdict;
    std::string reason;
};

struct SerialRun {
    std::map<std::string, Verdict> cases;
    std::string out;
};

SerialRun run_suite(const std::string& url, const std::vector<std::string>& choice) {
    const std::string json = temp_path("serial.json");
    std::vector<std::string> args{"conform", url, "--timeout", "600", "--json", json};
    args.insert(args.end(), choice.begin(), choice.end());
    auto ran = run_mblab(args);
    SerialRun run{{}, ran.out + ran.err};
    std::ifstream file(json);
    std::stringstream text;
    text << file.rdbuf();
    const auto report = nlohmann::json::parse(text.str(), nullptr, false);
    if (report.is_discarded()) return run;
    for (const auto& suite : report["suites"]) {
        for (const auto& c : suite["cases"]) {
            run.cases[c["id"]] = {c["verdict"], c.value("reason", std::string())};
        }
    }
    return run;
}

std::string line_url(const std::string& scheme, const PtyPair& pty) {
    return scheme + "://" + pty.client_end() + "?baud=19200&data=8";
}

SerialRun run_serial_suite(const std::string& url) {
    return run_suite(url, {"--suite", "serial"});
}

// Every case passes, but ser.8 (ASCII only) and, over RTU over TCP, the timing cases.
void passes_every_case(const SerialRun& run, bool ascii, bool serial_port = true) {
    ASSERT_EQ(run.cases.size(), 10U) << run.out;
    for (const auto& [id, v] : run.cases) {
        if ((id == "ser.8" && !ascii) || (!serial_port && (id == "ser.9" || id == "ser.10"))) {
            EXPECT_EQ(v.verdict, "N/A") << id;
            continue;
        }
        EXPECT_EQ(v.verdict, "PASS") << id << ": " << v.reason << "\n" << run.out;
    }
}

TEST(ConformSerialRules, ReferenceDevicePassesOverRtu) {
    DeviceOnLine line;
    ASSERT_EQ(line.start("reference", "rtu", 19200, false), "");
    auto run = run_serial_suite(line_url("rtu", line.pty()));
    passes_every_case(run, false);
    // The wrong CRC was counted by FC 08 sub-function 0C.
    EXPECT_NE(run.cases["ser.6"].reason.find("counted (1 bus communication errors)"),
              std::string::npos)
        << run.cases["ser.6"].reason;
}

TEST(ConformSerialRules, ReferenceDevicePassesOverAscii) {
    DeviceOnLine line;
    ASSERT_EQ(line.start("reference", "ascii", 19200, false), "");
    passes_every_case(run_serial_suite(line_url("ascii", line.pty())), true);
}

TEST(ConformSerialRules, ReferenceDevicePassesOverRtuOverTcp) {
    DeviceOnRtuTcp device;
    ASSERT_EQ(device.start(), "");
    const auto run = run_serial_suite("rtu+tcp://127.0.0.1:" + std::to_string(device.port()));
    passes_every_case(run, false, false);
    EXPECT_EQ(run.cases.at("ser.9").reason,
              "a line-timing test; over RTU over TCP frames are cut by their length, not by "
              "silence on a line");
}

// The timing cases say what they measured and how precisely a pty lets them see it.
TEST(ConformSerialRules, TheTimingCasesReportWhatTheyMeasured) {
    DeviceOnLine line;
    ASSERT_EQ(line.start("reference", "rtu", 19200, false), "");
    auto run = run_suite(line_url("rtu", line.pty()),
                         {"--suite", "serial", "--case", "ser.9", "--case", "ser.10"});
    // With ser.7, which both depend on: the answers they read must be well framed.
    ASSERT_EQ(run.cases.size(), 3U) << run.out;
    const std::string timing =
        "t1.5 = 0.86 ms and t3.5 = 2.01 ms at 19200 baud; over a pty the timing is logical";
    EXPECT_EQ(run.cases["ser.9"].verdict, "PASS") << run.cases["ser.9"].reason;
    EXPECT_NE(run.cases["ser.9"].reason.find("FC 06 broken by a 50 ms silence after its 4th byte "
                                             "was neither answered nor executed"),
              std::string::npos)
        << run.cases["ser.9"].reason;
    EXPECT_NE(run.cases["ser.9"].reason.find(timing), std::string::npos);
    EXPECT_EQ(run.cases["ser.10"].verdict, "PASS") << run.cases["ser.10"].reason;
    EXPECT_NE(run.cases["ser.10"].reason.find("10 reads answered, each sent t3.5 after the last "
                                              "answer: response time median "),
              std::string::npos)
        << run.cases["ser.10"].reason;
    EXPECT_NE(run.cases["ser.10"].reason.find("against a timeout of 600 ms"), std::string::npos);
    EXPECT_NE(run.cases["ser.10"].reason.find(timing), std::string::npos);
    // With pace=1 the tester's requests go out at the baud rate, and the reason says so. At
    // 1200 baud t3.5 is 32 ms, a silence no busy machine opens between two paced characters.
    DeviceOnLine slow;
    ASSERT_EQ(slow.start("reference", "rtu", 1200, false), "");
    auto paced = run_suite("rtu://" + slow.pty().client_end() + "?baud=1200&data=8&pace=1",
                           {"--suite", "serial", "--case", "ser.10"});
    EXPECT_EQ(paced.cases["ser.10"].verdict, "PASS") << paced.out;
    EXPECT_NE(paced.cases["ser.10"].reason.find(
                  "at 1200 baud; over a pty the tester sends at the baud rate (pace=1) and sees "
                  "the device's bytes as it writes them"),
              std::string::npos)
        << paced.cases["ser.10"].reason;
}

// The line's free address and the turnaround delay come from the DUT file when it declares them.
TEST(ConformSerialRules, TheDutFileSaysTheFreeAddressAndTheTurnaround) {
    DeviceOnLine line;
    ASSERT_EQ(line.start("reference", "rtu", 19200, false), "");
    const std::string dut = temp_path("line-dut.toml");
    std::ofstream(dut) << "unit = 1\nother_address = 9\nturnaround_ms = 50\n";
    auto run = run_suite(line_url("rtu", line.pty()),
                         {"--suite", "serial", "--case", "ser.1", "--case", "ser.3", "--dut", dut});
    EXPECT_EQ(run.cases["ser.1"].reason, "FC 03 to address 9 went unanswered for 600 ms")
        << run.out;
    EXPECT_EQ(run.cases["ser.3"].reason,
              "executed, unanswered, and the device answered 50 ms later")
        << run.out;
    std::ofstream(dut) << "other_address = 248\n";
    const auto refused = run_mblab({"conform", line_url("rtu", line.pty()), "--dut", dut});
    EXPECT_EQ(refused.status, 2);
    EXPECT_NE((refused.out + refused.err).find("other_address"), std::string::npos)
        << refused.out << refused.err;
}

// A slave set to other line settings than the URL's answers nothing: the settings the DUT file
// declares are tried, and the one-line error says which one it answers at and the URL to use.
TEST(ConformSerialRules, TheDeclaredLineSettingsAreTriedOnASilentDevice) {
    PtyPair pty;
    ASSERT_TRUE(pty.ok()) << pty.error();
    WrongSerialSlave slave;
    ASSERT_EQ(slave.start(pty, false, SlaveFault::SetTo9600N2), "");
    const std::string dut = temp_path("settings-dut.toml");
    std::ofstream(dut) << "unit = 1\nline_settings = [\"baud=19200&parity=O\", "
                          "\"baud=9600&parity=N&stop=2\"]\n";
    const auto url = "rtu://" + pty.client_end();
    const auto silent = run_mblab({"conform", url, "--dut", dut, "--timeout", "300"});
    EXPECT_EQ(silent.status, 2) << silent.out << silent.err;
    EXPECT_NE(silent.err.find("; it answers at baud=9600&parity=N&stop=2 (declared in "
                              "line_settings): run with rtu://" +
                              pty.client_end() + "?baud=9600&parity=N&stop=2&data=8\n"),
              std::string::npos)
        << silent.err;
    // At the URL it gives, the serial suite runs and the slave passes it.
    auto run =
        run_suite(url + "?baud=9600&parity=N&stop=2", {"--suite", "serial", "--case", "ser.1"});
    EXPECT_EQ(run.cases["ser.1"].verdict, "PASS") << run.out;
    // Without the declaration nothing is tried; a setting that is not one is refused in one line.
    std::ofstream(dut) << "unit = 1\n";
    const auto undeclared = run_mblab({"conform", url, "--dut", dut, "--timeout", "300"});
    EXPECT_EQ(undeclared.status, 2);
    EXPECT_EQ(undeclared.err.find("it answers at"), std::string::npos) << undeclared.err;
    std::ofstream(dut) << "line_settings = [\"baud=9600&units=1\"]\n";
    const auto refused = run_mblab({"conform", url, "--dut", dut});
    EXPECT_EQ(refused.status, 2);
    EXPECT_NE(refused.err.find("line_settings: 'baud=9600&units=1': a line setting is one of "
                               "baud, parity, stop and data"),
              std::string::npos)
        << refused.err;
}

TEST(ConformSerialRules, AnAsciiRequestWithAPauseUnderOneSecondIsTaken) {
    DeviceOnLine line;
    ASSERT_EQ(line.start("reference", "ascii", 19200, false), "");
    auto run = run_suite(line_url("ascii", line.pty()), {"--suite", "serial", "--case", "ser.9"});
    EXPECT_EQ(run.cases["ser.9"].verdict, "PASS") << run.out;
    EXPECT_EQ(run.cases["ser.9"].reason,
              "FC 03 with a 300 ms pause after its address was answered (up to 1 s is allowed "
              "between characters)");
}

// The case about the fault fails, with a reason that says what went wrong, and no other case
// does: every other one passes or is N/A (`also` names the other cases about the same rule).
void fails_with(SlaveFault fault, bool ascii, const std::string& id, const std::string& words,
                const std::vector<std::string>& also = {}) {
    PtyPair pty;
    ASSERT_TRUE(pty.ok()) << pty.error();
    WrongSerialSlave slave;
    ASSERT_EQ(slave.start(pty, ascii, fault), "");
    auto run = run_serial_suite(line_url(ascii ? "ascii" : "rtu", pty));
    ASSERT_TRUE(run.cases.contains(id)) << run.out;
    EXPECT_EQ(run.cases[id].verdict, "FAIL") << run.out;
    EXPECT_NE(run.cases[id].reason.find(words), std::string::npos)
        << id << ": " << run.cases[id].reason;
    for (const auto& [other, v] : run.cases) {
        if (other == id || std::find(also.begin(), also.end(), other) != also.end()) continue;
        EXPECT_NE(v.verdict, "FAIL")
            << "the fault is about " << id << ", yet " << other << " failed: " << v.reason;
    }
}

TEST(ConformSerialRules, TheSlaveKeepingTheRulesPasses) {
    PtyPair pty;
    ASSERT_TRUE(pty.ok()) << pty.error();
    WrongSerialSlave slave;
    ASSERT_EQ(slave.start(pty, false, SlaveFault::None), "");
    const auto run = run_serial_suite(line_url("rtu", pty));
    EXPECT_EQ(run.cases.size(), 10U) << run.out;
    for (const auto& [id, v] : run.cases) {
        if (id == "ser.8") continue;
        EXPECT_EQ(v.verdict, "PASS") << id << ": " << v.reason;
    }
}

TEST(ConformSerialRules, ASlaveJoiningAFrameBrokenBySilenceFails) {
    fails_with(SlaveFault::JoinsBrokenFrame, false, "ser.9",
               "FC 06 broken by a 50 ms silence after its 4th byte was answered");
}

TEST(ConformSerialRules, ASlaveBreakingItsAnswerWithAGapFails) {
    fails_with(SlaveFault::GapInAnswer, false, "ser.10", "ms inside the answer; at most t1.5");
}

TEST(ConformSerialRules, ASlaveAnsweringAnotherAddressFails) {
    fails_with(SlaveFault::AnswersOtherAddress, false, "ser.1",
               "FC 03 to address 2 (not the device's 1) was answered", {"ser.2"});
    fails_with(SlaveFault::AnswersOtherAddress, false, "ser.2",
               "FC 06 to address 2 (not the device's 1) was answered", {"ser.1"});
}

TEST(ConformSerialRules, ASlaveAnsweringABroadcastFails) {
    // ser.3, ser.4 and ser.5 are the three broadcast cases.
    fails_with(SlaveFault::AnswersBroadcast, false, "ser.3", "FC 06 to address 0 was answered",
               {"ser.4", "ser.5"});
    fails_with(SlaveFault::AnswersBroadcast, false, "ser.4", "FC 03 to address 0 was answered",
               {"ser.3", "ser.5"});
    fails_with(SlaveFault::AnswersBroadcast, true, "ser.5",
               "FC 08 (return query data) to address 0 was answered", {"ser.3", "ser.4"});
}

TEST(ConformSerialRules, ASlaveExecutingABadCrcFails) {
    // The two parts of ser.9's broken frame are frames with a wrong CRC too: this slave takes
    // the first and answers it.
    fails_with(SlaveFault::ExecutesBadChecksum, false, "ser.6",
               "FC 06 with a wrong CRC was answered", {"ser.9"});
    fails_with(SlaveFault::ExecutesBadChecksum, true, "ser.6",
               "FC 06 with a wrong LRC was answered");
}

TEST(ConformSerialRules, AnAsciiSlaveAnsweringInLowerCaseFailsForThat) {
    fails_with(SlaveFault::LowerCaseAnswer, true, "ser.7", "lower-case hex digit");
}

TEST(ConformSerialRules, AnAsciiSlaveEndingWithCrAloneFailsForThat) {
    fails_with(SlaveFault::CrWithoutLf, true, "ser.7", "CR not followed by 0x0A (LF)");
}

TEST(ConformSerialRules, AnAsciiSlaveWithAWrongLrcFailsForThat) {
    fails_with(SlaveFault::WrongLrc, true, "ser.7", "LRC mismatch");
}

// Any case's answer is judged as it came: a malformed frame is named, never "no answer".
TEST(ConformSerialRules, AMalformedAsciiAnswerIsNamedInEveryCase) {
    for (const auto& [fault, words] : {std::pair{SlaveFault::LowerCaseAnswer, "lower-case hex"},
                                       std::pair{SlaveFault::WrongLrc, "LRC mismatch"}}) {
        PtyPair pty;
        ASSERT_TRUE(pty.ok()) << pty.error();
        WrongSerialSlave slave;
        ASSERT_EQ(slave.start(pty, true, fault), "");
        // The answer to 7.3.1 (FC 01, one coil) has letters among its hex digits.
        auto run = run_suite(line_url("ascii", pty), {"--suite", "policy-2.1", "--case", "7.3.1"});
        for (const char* id : {"7.3.1"}) {
            EXPECT_EQ(run.cases[id].verdict, "FAIL") << run.out;
            EXPECT_NE(run.cases[id].reason.find(std::string("malformed answer: ") + words),
                      std::string::npos)
                << id << ": " << run.cases[id].reason;
        }
    }
}

TEST(ConformSerialRules, AnRtuSlaveSendingTheCrcHighByteFirstFails) {
    fails_with(SlaveFault::CrcHighByteFirst, false, "ser.7", "is sent high byte first");
}

TEST(ConformSerialRules, ASlaveAnsweringWithAnotherAddressFails) {
    fails_with(SlaveFault::ForeignAddressInAnswer, false, "ser.7",
               "an answer carrying address 2 where the device's is 1");
}

}  // namespace
}  // namespace mblab::test
