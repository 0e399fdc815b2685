// Verdicts a device cannot game: a close the case allows does not pass when the close was a
// crash; exception 01 makes a case N/A only when the function is truly not served; an optional
// access refused as the spec allows is N/A, not FAIL.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include "conformance/catalogue.hpp"
#include "conformance/device_dut.hpp"
#include "conformance/engine.hpp"
#include "device/reference_device.hpp"
#include "server/background_server.hpp"
#include "support/device_profiles.hpp"
#include "support/faulty_server.hpp"
#include "support/rewriting_handler.hpp"

namespace mblab::conformance {
namespace {

std::unique_ptr<device::ReferenceDevice> reference_device() {
    return test::shipped_device("reference");
}

// One [[case]] of a suite; `more` holds any further keys, a line each.
std::string case_toml(const std::string& id, const std::string& title, const std::string& request,
                      const std::string& expect, const std::string& more = "") {
    return "[[case]]\nsource = \"test\"\nid = \"" + id + "\"\ntitle = \"" + title + "\"\n" + more +
           "request = \"" + request + "\"\nexpect = \"" + expect + "\"\n";
}

Suite suite_of(const std::string& text) {
    auto suite = load_suite_text("[suite]\nname = \"t\"\n" + text, "t.toml");
    EXPECT_TRUE(suite.ok()) << suite.error();
    return suite.value();
}

RunResult run(std::uint16_t port, const Suite& suite) {
    EngineOptions options;
    options.timeout = std::chrono::milliseconds(400);
    Dut dut;
    Session session({"127.0.0.1", port}, dut, options);
    client::LinkError error;
    EXPECT_TRUE(session.connect(error)) << error.message;
    Engine engine(session);
    return engine.run({suite}, "test");
}

const CaseResult& at(const RunResult& result, std::size_t i) {
    return result.suites.at(0).cases.at(i);
}

using Rewriting = test::RewritingHandler;

const std::string kCloseAllowed =
    case_toml("close", "a request the device may refuse by closing",
              "00 01 00 00 00 06 01 04 00 00 00 01", "00 01 00 00 00 03 01 84 03",
              "accept_close = \"closed the connection\"\n") +
    case_toml("after", "a read after it", "00 02 00 00 00 06 01 03 00 00 00 01",
              "00 02 00 00 00 05 01 03 02 XX XX");

// How the tester judges a case: the verdict, and a matcher for its reason.
struct Judged {
    Verdict verdict;
    ::testing::Matcher<std::string> reason = ::testing::_;
};

void expect_judged(const RunResult& result, std::size_t i, const Judged& expected) {
    const auto& outcome = at(result, i).outcome;
    EXPECT_EQ(outcome.verdict, expected.verdict) << "case " << i << ": " << outcome.reason;
    EXPECT_THAT(outcome.reason, expected.reason) << "case " << i;
}

// kCloseAllowed against a device whose FC 04 answer is `fault`.
struct CloseCase {
    std::string name;
    test::Fault fault;
    Judged close;
    Judged after;
    bool all_passed;
};

void PrintTo(const CloseCase& row, std::ostream* out) {
    *out << row.name;
}

using ::testing::Eq;
using ::testing::HasSubstr;
using ::testing::StartsWith;

const CloseCase kCloses[] = {
    {"AnAllowedCloseFromADeviceThatStillServesPasses",
     test::Fault::CloseConnection,
     {Verdict::Pass, Eq("closed the connection")},
     {Verdict::Pass},
     true},
    // A device with one connection slot that takes a moment to free it refuses the tester's
    // next connection at first; it is still serving, so neither the close nor the next case
    // fails.
    {"ADeviceSlowToTakeANewConnectionAfterAnAllowedCloseStillPasses",
     test::Fault::SlowToReopen,
     {Verdict::Pass},
     {Verdict::Pass},
     true},
    {"AnAllowedCloseThatWasACrashFailsAndSoDoesEveryCaseAfterIt",
     test::Fault::Dies,
     {Verdict::Fail, StartsWith("closed the connection, but afterwards the device refused a new "
                                "connection: ")},
     {Verdict::Fail,
      StartsWith("the device no longer accepts connections (it did earlier in the run): ")},
     false},
};

class ConformCloseVerdicts : public ::testing::TestWithParam<CloseCase> {};

TEST_P(ConformCloseVerdicts, JudgeTheCloseByWhetherTheDeviceStillServes) {
    auto device = reference_device();
    test::FaultyServer server(*device, {GetParam().fault, 0x04, 0});
    const auto port = server.start();
    auto result = run(port, suite_of(kCloseAllowed));
    expect_judged(result, 0, GetParam().close);
    expect_judged(result, 1, GetParam().after);
    EXPECT_EQ(result.all_passed(), GetParam().all_passed);
}

INSTANTIATE_TEST_SUITE_P(Fault, ConformCloseVerdicts, ::testing::ValuesIn(kCloses),
                         [](const auto& info) { return info.param.name; });

// The run of `suite` against `device` served with its answers rewritten by `rule`.
RunResult run_rewritten(device::RequestHandler& device, const Rewriting::Rule& rule,
                        const Suite& suite) {
    Rewriting handler(device, rule);
    server::BackgroundServer server(handler);
    const auto port = server.start();
    EXPECT_TRUE(port.ok());
    return run(port.ok() ? *port : 0, suite);
}

// FC 03 with a quantity of 0 must be answered 03 ([APP] 6.3); this device answers 01.
const Rewriting::Rule kQuantity0Answered01 =
    [](std::span<const std::uint8_t> request) -> std::optional<std::vector<std::uint8_t>> {
    if (request.size() == 5 && request[0] == 0x03 && request[3] == 0 && request[4] == 0) {
        return std::vector<std::uint8_t>{0x83, 0x01};
    }
    return std::nullopt;
};

const std::string kQuantity0 =
    case_toml("q0", "FC 03 of 0 registers answers 03", "00 03 00 00 00 06 01 03 00 00 00 00",
              "00 03 00 00 00 03 01 83 03", "unsupported_is_na = true\n");

TEST(ConformVerdicts, Exception01FromAFunctionServedEarlierInTheRunFails) {
    auto device = reference_device();
    auto result = run_rewritten(
        *device, kQuantity0Answered01,
        suite_of(case_toml("read", "FC 03 reads", "00 01 00 00 00 06 01 03 00 00 00 01",
                           "00 01 00 00 00 05 01 03 02 XX XX") +
                 kQuantity0));
    expect_judged(result, 0, {Verdict::Pass});
    expect_judged(result, 1,
                  {Verdict::Fail, Eq("exception 01 (illegal function), yet the device serves "
                                     "function 03 (it answered it otherwise earlier in this "
                                     "run): 01 says a function is not served")});
}

TEST(ConformVerdicts, Exception01FromAFunctionWhosePlainRequestIsAnsweredFails) {
    auto device = reference_device();
    auto result = run_rewritten(*device, kQuantity0Answered01, suite_of(kQuantity0));
    expect_judged(result, 0,
                  {Verdict::Fail, HasSubstr("yet the device serves function 03 (its plain "
                                            "request was answered 7E 57 00 00 00 05 01 03 02")});
}

// FC 06 to register 5 is answered 01 by a device that serves FC 06. Finding that out must not
// change the device's data: the tester writes register 0's own value back to it.
TEST(ConformVerdicts, TellingAServedWriteFromAnUnservedOneChangesNoData) {
    auto device = test::device_from(R"(
name = "ten registers"
[[unit]]
id = 1
holding_registers = [{start = 0, count = 10}]
)");
    ASSERT_TRUE(device);
    const Rewriting::Rule fc06_at_5_answered_01 =
        [](std::span<const std::uint8_t> request) -> std::optional<std::vector<std::uint8_t>> {
        if (request.size() == 5 && request[0] == 0x06 && request[2] == 0x05) {
            return std::vector<std::uint8_t>{0x86, 0x01};
        }
        return std::nullopt;
    };
    auto result = run_rewritten(
        *device, fc06_at_5_answered_01,
        suite_of(case_toml("set", "FC 10 puts BEEF in register 0",
                           "00 01 00 00 00 09 01 10 00 00 00 01 02 BE EF",
                           "00 01 00 00 00 06 01 10 00 00 00 01") +
                 case_toml("fc06", "FC 06 writes register 5", "00 02 00 00 00 06 01 06 00 05 12 34",
                           "00 02 00 00 00 06 01 06 00 05 12 34", "unsupported_is_na = true\n") +
                 case_toml("after", "register 0 still holds BEEF",
                           "00 03 00 00 00 06 01 03 00 00 00 01",
                           "00 03 00 00 00 05 01 03 02 BE EF")));
    expect_judged(result, 0, {Verdict::Pass});
    expect_judged(result, 1,
                  {Verdict::Fail, HasSubstr("yet the device serves function 06 (its plain "
                                            "request was answered 7E 57 00 00 00 06 01 06 00 00 "
                                            "BE EF")});
    expect_judged(result, 2, {Verdict::Pass});
}

TEST(ConformVerdicts, Exception01FromAFunctionNotServedIsNotApplicable) {
    auto device = reference_device();
    test::FaultyServer server(*device, {test::Fault::IllegalFunction, 0x03, 0});
    const auto port = server.start();
    auto result = run(port, suite_of(kQuantity0));
    expect_judged(result, 0,
                  {Verdict::NotApplicable,
                   Eq("the device answered exception 01: function 03 is not supported")});
}

// Individual access (read code 04) answered 03, from a device whose conformity level declares
// stream access only (01) or individual access as well (81).
Rewriting::Rule individual_access_refused(std::uint8_t level) {
    return
        [level](std::span<const std::uint8_t> request) -> std::optional<std::vector<std::uint8_t>> {
            if (request.size() == 4 && request[0] == 0x2B && request[1] == 0x0E) {
                if (request[2] == 0x04) return std::vector<std::uint8_t>{0xAB, 0x03};
                if (request[2] == 0x01 && request[3] == 0x00) {
                    // Basic stream: one object (vendor name "V"), nothing more follows.
                    return std::vector<std::uint8_t>{0x2B, 0x0E, 0x01, level, 0x00,
                                                     0x00, 0x01, 0x00, 0x01,  'V'};
                }
            }
            return std::nullopt;
        };
}

// The device-id cases `judged` against a device at conformity `level` that refuses individual
// access; the other cases are not this table's concern.
struct IndividualAccessCase {
    std::string name;
    std::uint8_t level;
    std::vector<std::string> judged;
    Judged expected;
};

void PrintTo(const IndividualAccessCase& row, std::ostream* out) {
    *out << row.name;
}

const IndividualAccessCase kIndividualAccess[] = {
    {"RefusedByAStreamOnlyDeviceIsNotApplicable",
     0x01,
     {"devid.2", "devid.5"},
     {Verdict::NotApplicable,
      Eq("the device answered exception 03 to individual access, and its conformity level 01 "
         "declares stream access only")}},
    {"RefusedByADeviceThatDeclaresItFails",
     0x81,
     {"devid.2"},
     {Verdict::Fail, Eq("exception 03 (illegal data value) where data was expected")}},
};

class ConformIndividualAccess : public ::testing::TestWithParam<IndividualAccessCase> {};

TEST_P(ConformIndividualAccess, IsJudgedByTheDeclaredConformityLevel) {
    auto device = reference_device();
    Rewriting handler(*device, individual_access_refused(GetParam().level));
    server::BackgroundServer server(handler);
    const auto port = server.start();
    ASSERT_TRUE(port.ok());
    auto suite = load_suite_file(std::string(MBLAB_SOURCE_DIR) + "/catalogue/device-id.toml");
    ASSERT_TRUE(suite.ok());
    auto result = run(*port, suite.value());
    const auto& cases = result.suites.at(0).cases;
    for (std::size_t i = 0; i < cases.size(); ++i) {
        const auto& judged = GetParam().judged;
        if (std::find(judged.begin(), judged.end(), cases[i].id) == judged.end()) continue;
        SCOPED_TRACE(cases[i].id);
        expect_judged(result, i, GetParam().expected);
    }
}

INSTANTIATE_TEST_SUITE_P(Level, ConformIndividualAccess, ::testing::ValuesIn(kIndividualAccess),
                         [](const auto& info) { return info.param.name; });

}  // namespace
}  // namespace mblab::conformance
