#include <gtest/gtest.h>

#include <algorithm>
#include <regex>

#include "conformance/catalogue.hpp"
#include "conformance/device_dut.hpp"
#include "conformance/engine.hpp"
#include "device/reference_device.hpp"
#include "support/faulty_server.hpp"
#include "support/ports.hpp"

// The tester against devices that are wrong on purpose: each kind of defect must be caught by
// the case that exercises it, and devices that are right but unusual must pass.
namespace mblab::conformance {
namespace {

using test::Fault;
using test::FaultRule;

const std::string kProfile = std::string(MBLAB_SOURCE_DIR) + "/profiles/reference.toml";

class FaultyDeviceRun {
  public:
    explicit FaultyDeviceRun(FaultRule rule, EngineOptions options = quick()) : options_(options) {
        auto profile = device::read_profile(kProfile);
        EXPECT_TRUE(profile.ok());
        dut_ = dut_from_profile(profile.value(), "test");
        device_ = std::make_unique<device::ReferenceDevice>(std::move(profile.value()));
        server_ = std::make_unique<test::FaultyServer>(*device_, rule);
        port_ = server_->start();
        EXPECT_NE(port_, 0);
    }

    // The policy suite without the ping, which depends on the machine rather than the device.
    RunResult run_policy() { return run_suite("policy-2.1"); }

    RunResult run_suite(const std::string& name) {
        auto suite =
            load_suite_file(std::string(MBLAB_SOURCE_DIR) + "/catalogue/" + name + ".toml");
        EXPECT_TRUE(suite.ok());
        auto& cases = suite->cases;
        cases.erase(std::remove_if(cases.begin(), cases.end(),
                                   [](const Case& c) { return c.procedure == "ping"; }),
                    cases.end());
        Session session({"127.0.0.1", port_}, dut_, options_);
        Engine engine(session);
        return engine.run({suite.value()}, "faulty");
    }

    static EngineOptions quick() {
        EngineOptions options;
        options.timeout = std::chrono::milliseconds(400);
        return options;
    }

    // What the user declares; starts as the reference profile declares it.
    Dut& dut() { return dut_; }

  private:
    EngineOptions options_;
    Dut dut_;
    std::unique_ptr<device::ReferenceDevice> device_;
    std::unique_ptr<test::FaultyServer> server_;
    std::uint16_t port_ = 0;
};

const CaseResult& find(const RunResult& run, const std::string& id) {
    for (const auto& c : run.suites.at(0).cases) {
        if (c.id == id) return c;
    }
    throw std::runtime_error("no case " + id);
}

// Every case but `failing` passes (or is NOT RUN when listed in `blocked`).
void expect_only_failures(const RunResult& run, const std::vector<std::string>& failing,
                          const std::vector<std::string>& blocked = {}) {
    for (const auto& c : run.suites.at(0).cases) {
        Verdict want = Verdict::Pass;
        if (std::count(failing.begin(), failing.end(), c.id)) want = Verdict::Fail;
        if (std::count(blocked.begin(), blocked.end(), c.id)) want = Verdict::NotRun;
        EXPECT_EQ(verdict_label(c.outcome.verdict), verdict_label(want))
            << c.id << ": " << c.outcome.reason;
    }
}

TEST(ConformFaults, ACorrectDevicePassesEveryCase) {
    FaultyDeviceRun device({Fault::None, 0});
    auto run = device.run_policy();
    expect_only_failures(run, {});
    EXPECT_EQ(run.counts().passed, 17U);
}

TEST(ConformFaults, WrongTransactionIdIsCaught) {
    FaultyDeviceRun device({Fault::WrongTransactionId, 0x01});
    auto run = device.run_policy();
    // FC 01 also reads back the coil writes of 7.7.1 and 7.11.1.
    expect_only_failures(run, {"7.3.1", "7.7.1", "7.11.1"});
    EXPECT_EQ(find(run, "7.7.1").outcome.reason, "step 2 of 4: wrong transaction id");
    const auto& c = find(run, "7.3.1");
    EXPECT_EQ(c.outcome.reason, "wrong transaction id");
    ASSERT_EQ(c.outcome.evidence.size(), 1U);
    EXPECT_EQ(c.outcome.evidence[0].match.differs, std::vector<std::size_t>{1});
}

TEST(ConformFaults, WrongLengthFieldIsCaughtEverywhereFc03IsUsed) {
    FaultyDeviceRun device({Fault::WrongLength, 0x03});
    auto run = device.run_policy();
    // 9.1.3 is answered after the partial-frame wait, not by the faulty answer path.
    expect_only_failures(run, {"7.5.1", "7.5.2", "7.8.1", "7.12.1", "9.1.2", "9.1.4"}, {"7.13.2"});
    EXPECT_EQ(find(run, "7.5.1").outcome.reason, "wrong length field, missing bytes");
    EXPECT_EQ(find(run, "7.13.2").outcome.reason, "7.5.1 did not pass (FAIL)");
    EXPECT_EQ(find(run, "7.5.2").outcome.reason,
              "phase 1 (growing reads at 0000), read of 1 registers at 0000: wrong length "
              "field, missing bytes");
}

TEST(ConformFaults, WrongUnitIdIsCaught) {
    FaultyDeviceRun device({Fault::WrongUnitId, 0x02});
    auto run = device.run_policy();
    expect_only_failures(run, {"7.4.1"});
    EXPECT_EQ(find(run, "7.4.1").outcome.reason, "wrong unit id");
}

TEST(ConformFaults, WrongByteCountIsCaughtInTheSweep) {
    FaultyDeviceRun device({Fault::WrongByteCount, 0x03});
    auto run = device.run_policy();
    expect_only_failures(run, {"7.5.1", "7.5.2", "7.8.1", "7.12.1"}, {"7.13.2"});
    EXPECT_EQ(find(run, "7.5.1").outcome.evidence.at(0).match.differs, std::vector<std::size_t>{8});
    EXPECT_EQ(find(run, "7.5.1").outcome.reason, "wrong byte count");
}

TEST(ConformFaults, WrongExceptionCodeIsCaught) {
    FaultyDeviceRun device({Fault::WrongExceptionCode, 0x25});
    auto run = device.run_policy();
    expect_only_failures(run, {"9.1.1"});
    EXPECT_EQ(find(run, "9.1.1").outcome.reason,
              "exception 04 (server device failure) instead of 01");
}

TEST(ConformFaults, MissingAnswerIsCaughtAndTheRunGoesOn) {
    FaultyDeviceRun device({Fault::NoAnswer, 0x07});
    auto run = device.run_policy();
    expect_only_failures(run, {"7.9.1"});
    // The unit asked, how many requests the connection had carried, and the other units tried.
    const std::string reason = find(run, "7.9.1").outcome.reason;
    EXPECT_TRUE(std::regex_search(
        reason, std::regex("^no answer from unit 1: timeout after 400 ms \\(request [0-9]+ on "
                           "this connection\\)")))
        << reason;
    // The device answers a read on unit 1: the unit is not the problem, so none is suggested.
    EXPECT_EQ(reason.find("--unit"), std::string::npos) << reason;
}

TEST(ConformFaults, ClosedConnectionIsCaughtAndTheRunReconnects) {
    FaultyDeviceRun device({Fault::CloseConnection, 0x08});
    auto run = device.run_policy();
    expect_only_failures(run, {"7.10.1"});
    EXPECT_TRUE(std::regex_search(find(run, "7.10.1").outcome.reason,
                                  std::regex("^no answer from unit 1: connection closed by peer "
                                             "\\(request [0-9]+ on this connection\\)$")))
        << find(run, "7.10.1").outcome.reason;
}

TEST(ConformFaults, WrongEchoIsCaught) {
    FaultyDeviceRun device({Fault::WrongEcho, 0x06});
    auto run = device.run_policy();
    expect_only_failures(run, {"7.8.1"});
    EXPECT_EQ(find(run, "7.8.1").outcome.evidence.at(0).match.differs,
              std::vector<std::size_t>{11});
}

TEST(ConformFaults, AnswersSplitOverSegmentsPass) {
    for (std::uint8_t function : {0x01, 0x5B, 0x25}) {
        FaultyDeviceRun device({Fault::SplitAnswer, function});
        expect_only_failures(device.run_policy(), {});
    }
}

TEST(ConformFaults, PipelinedAnswersInAnotherOrderPass) {
    FaultyDeviceRun device({Fault::ReorderAnswers, 0});
    auto run = device.run_suite("mbap");
    EXPECT_EQ(verdict_label(find(run, "mbap.6").outcome.verdict), "PASS")
        << find(run, "mbap.6").outcome.reason;
    EXPECT_EQ(run.counts().failed, 0U);
}

TEST(ConformFaults, AnswersLateBy150MsPass) {
    for (std::uint8_t function : {0x02, 0x10}) {
        FaultyDeviceRun device({Fault::LateAnswer, function});
        expect_only_failures(device.run_policy(), {});
    }
}

bool has(const std::string& text, const std::string& words) {
    return text.find(words) != std::string::npos;
}

// Case `id` of `run` FAILed, for a reason that holds `words`.
void expect_failed(const RunResult& run, const std::string& id, const std::string& words) {
    const auto& c = find(run, id);
    EXPECT_EQ(verdict_label(c.outcome.verdict), "FAIL") << id << ": " << c.outcome.reason;
    EXPECT_TRUE(has(c.outcome.reason, words)) << id << ": " << c.outcome.reason;
}

EngineOptions pipelined(std::size_t depth) {
    EngineOptions options = FaultyDeviceRun::quick();
    options.pipeline_depth = depth;
    return options;
}

// --- conformant but unusual: must pass ------------------------------------------------------

TEST(ConformFaults, PipelinedSweepAnsweredOutOfOrderPasses) {
    FaultyDeviceRun device({Fault::ReorderAnswers, 0}, pipelined(16));
    auto run = device.run_policy();
    expect_only_failures(run, {});
    EXPECT_TRUE(has(find(run, "7.5.2").outcome.reason, "pipelined 16 deep"))
        << find(run, "7.5.2").outcome.reason;
    EXPECT_TRUE(has(find(run, "7.13.2").outcome.reason, "signature at register 0000"));
}

TEST(ConformFaults, BusyAnswersToPipelinedReadsAreBackPressureNotFailures) {
    FaultyDeviceRun device({Fault::BusyWhenQueued, 0}, pipelined(16));
    auto run = device.run_policy();
    expect_only_failures(run, {});
    const std::string& sweep = find(run, "7.5.2").outcome.reason;
    EXPECT_TRUE(has(sweep, "pipelined 16 deep; the device answered 06 (busy)")) << sweep;
    // How far the depth comes down depends on how many requests the device finds queued, which
    // is timing (ASan builds see 8 as often as 1); that it came down is the behaviour.
    EXPECT_TRUE(has(sweep, "depth lowered to ")) << sweep;
    // mbap.6 pipelines three requests: two busy answers are back-pressure as well.
    auto mbap = device.run_suite("mbap");
    EXPECT_EQ(mbap.counts().failed, 0U);
    EXPECT_TRUE(has(find(mbap, "mbap.6").outcome.reason,
                    "2 of 3 pipelined requests were "
                    "answered 06 (busy)"))
        << find(mbap, "mbap.6").outcome.reason;
}

TEST(ConformFaults, ByDefaultTheSweepRunsAsThePolicyWritesIt) {
    // A device that cannot queue requests at all passes: one request at a time, transaction 0.
    FaultyDeviceRun device({Fault::BusyWhenQueued, 0});
    auto run = device.run_policy();
    expect_only_failures(run, {});
    EXPECT_TRUE(has(find(run, "7.5.2").outcome.reason,
                    "775 reads of up to 125 registers over 65536 registers, one request at a time"))
        << find(run, "7.5.2").outcome.reason;
}

TEST(ConformFaults, AnOptionalFunctionMissingInALaterStepMakesTheCaseNotApplicable) {
    FaultyDeviceRun device({Fault::IllegalFunction, 0x16});
    auto run = device.run_suite("function-codes");
    const auto& c = find(run, "fc16.1");
    EXPECT_EQ(verdict_label(c.outcome.verdict), "N/A") << c.outcome.reason;
    EXPECT_EQ(c.outcome.reason,
              "the device answered exception 01: function 16 is not supported (step 2 of 3)");
    EXPECT_EQ(run.counts().failed, 0U);
}

TEST(ConformFaults, OutOfRangeWithoutADeclaredCountDecidesPastTheEnd) {
    // The reference device has all 65536 registers, so 0x8001 answers data.
    FaultyDeviceRun device({Fault::None, 0});
    device.dut().registers.reset();
    auto run = device.run_policy();
    const auto& c = find(run, "9.1.2");
    EXPECT_EQ(verdict_label(c.outcome.verdict), "PASS") << c.outcome.reason;
    EXPECT_TRUE(has(c.outcome.reason,
                    "read of 2 registers at FFFF, past the end of the address "
                    "space, answered 02 and decided the verdict"))
        << c.outcome.reason;
}

// --- defective: must fail on the right case, naming the fault ------------------------------

TEST(ConformFaults, OutOfRangeDataPastTheEndFailsNamingTheDecidingRead) {
    FaultyDeviceRun device({Fault::DataPastTheEnd, 0x03});
    device.dut().registers.reset();
    expect_failed(device.run_policy(), "9.1.2",
                  "so the read past the end decides: read of 2 registers at FFFF: answered "
                  "with data where exception 02 (illegal data address) was expected");
}

TEST(ConformFaults, ADuplicateAnswerFailsTheCaseThatProvokedIt) {
    for (std::uint8_t function : {0x06, 0x07}) {
        FaultyDeviceRun device({Fault::DuplicateAnswer, function});
        auto run = device.run_policy();
        const std::string id = function == 0x06 ? "7.8.1" : "7.9.1";
        expect_only_failures(run, {id});
        EXPECT_TRUE(has(find(run, id).outcome.reason, "duplicate answer"))
            << find(run, id).outcome.reason;
    }
}

TEST(ConformFaults, UnsolicitedBytesFailTheCaseThatProvokedThemWithTheBytes) {
    FaultyDeviceRun device({Fault::UnsolicitedBytes, 0x07});
    auto run = device.run_policy();
    expect_only_failures(run, {"7.9.1"});
    const auto& c = find(run, "7.9.1");
    EXPECT_TRUE(has(c.outcome.reason,
                    "unsolicited bytes: after the case's last answer, the "
                    "device sent 6 bytes nobody asked for"))
        << c.outcome.reason;
    EXPECT_TRUE(has(c.outcome.reason, "DE AD BE EF 00 01")) << c.outcome.reason;
}

TEST(ConformFaults, WritesAcknowledgedButNotMadeFailWithTheFlagsAlone) {
    FaultyDeviceRun device({Fault::WriteNotApplied, 0});
    device.dut() = Dut{};  // the standard flags only: nothing declared but the unit
    device.dut().unit = 1;
    auto run = device.run_policy();
    for (const char* id : {"7.7.1", "7.8.1", "7.11.1", "7.12.1"}) {
        const auto& c = find(run, id);
        EXPECT_EQ(verdict_label(c.outcome.verdict), "FAIL") << id << ": " << c.outcome.reason;
        EXPECT_TRUE(std::regex_search(c.outcome.reason,
                                      std::regex("^step [24] of 4: wrong (bit|register) values$")))
            << id << ": " << c.outcome.reason;
    }
}

TEST(ConformFaults, PadBitsSetInAReadCoilsAnswerAreCaught) {
    FaultyDeviceRun device({Fault::PadBitsSet, 0x01});
    expect_failed(device.run_policy(), "7.3.1",
                  "unused bits of the last data byte: 80 holds bits set past the 1 requested "
                  "(mask 80); they must be zero");
}

TEST(ConformFaults, DeviceIdObjectsPastThePduAreCaught) {
    FaultyDeviceRun device({Fault::DeviceIdPastPdu, 0x2B});
    expect_failed(device.run_suite("device-id"), "devid.1", "object length");
}

TEST(ConformFaults, AMoreFollowsThatNeverEndsIsCaught) {
    FaultyDeviceRun device({Fault::DeviceIdEndless, 0x2B});
    expect_failed(device.run_suite("device-id"), "devid.1", "more follows never ends");
}

TEST(ConformFaults, DeviceIdObjectsBeyondTheConformityLevelAreCaught) {
    FaultyDeviceRun device({Fault::DeviceIdBasicLevel, 0x2B});
    auto run = device.run_suite("device-id");
    expect_failed(run, "devid.9", "object 03 is beyond conformity level 81");
    EXPECT_EQ(verdict_label(find(run, "devid.1").outcome.verdict), "PASS");
}

TEST(ConformFaults, ADeviceThatStopsAfterNRequestsShowsInTheReport) {
    FaultyDeviceRun device({Fault::SilentAfter, 0, 5});
    auto run = device.run_policy();
    bool seen = false;
    for (const auto& c : run.suites.at(0).cases) {
        if (c.outcome.verdict == Verdict::Fail &&
            has(c.outcome.reason, "(request 6 on this connection)")) {
            seen = true;
        }
    }
    EXPECT_TRUE(seen);
}

TEST(ConformFaults, NoAnswerSuggestsTheUnitTheDeviceAnswers) {
    FaultyDeviceRun device({Fault::OnlyUnit255, 0});
    auto run = device.run_policy();
    expect_failed(run, "7.3.1", "no answer from unit 1: timeout after 400 ms");
    expect_failed(run, "7.3.1", "; the device answers unit 255: try --unit 255");
}

TEST(ConformFaults, CasesAfterTheDeviceWentAwayAreNotRun) {
    auto suite = load_suite_file(std::string(MBLAB_SOURCE_DIR) + "/catalogue/policy-2.1.toml");
    ASSERT_TRUE(suite.ok());
    Dut dut;
    dut.registers = 100;
    Session session({"127.0.0.1", test::closed_port()}, dut, EngineOptions{});
    Engine engine(session);
    auto run = engine.run({suite.value()}, "gone");
    for (const char* id : {"7.3.1", "7.5.2", "9.1.3"}) {
        EXPECT_EQ(verdict_label(find(run, id).outcome.verdict), "NOT RUN") << id;
        EXPECT_EQ(find(run, id).outcome.reason, "cannot connect to the device: connection refused");
    }
    EXPECT_EQ(run.counts().failed, 0U);
}

}  // namespace
}  // namespace mblab::conformance
