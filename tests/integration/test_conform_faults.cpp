#include <gtest/gtest.h>

#include <algorithm>

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
    explicit FaultyDeviceRun(FaultRule rule) {
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
        EngineOptions options;
        options.timeout = std::chrono::milliseconds(400);
        Session session({"127.0.0.1", port_}, dut_, options);
        Engine engine(session);
        return engine.run({suite.value()}, "faulty");
    }

  private:
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
    expect_only_failures(run, {"7.3.1"});
    const auto& c = find(run, "7.3.1");
    EXPECT_EQ(c.outcome.reason, "wrong transaction id");
    ASSERT_EQ(c.outcome.evidence.size(), 1U);
    EXPECT_EQ(c.outcome.evidence[0].match.differs, std::vector<std::size_t>{1});
}

TEST(ConformFaults, WrongLengthFieldIsCaughtEverywhereFc03IsUsed) {
    FaultyDeviceRun device({Fault::WrongLength, 0x03});
    auto run = device.run_policy();
    // 9.1.3 is answered after the partial-frame wait, not by the faulty answer path.
    expect_only_failures(run, {"7.5.1", "7.5.2", "9.1.2", "9.1.4"}, {"7.13.2"});
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
    expect_only_failures(run, {"7.5.1", "7.5.2"}, {"7.13.2"});
    EXPECT_EQ(find(run, "7.5.1").outcome.evidence.at(0).match.differs, std::vector<std::size_t>{8});
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
    EXPECT_EQ(find(run, "7.9.1").outcome.reason, "no answer: timeout after 400 ms");
}

TEST(ConformFaults, ClosedConnectionIsCaughtAndTheRunReconnects) {
    FaultyDeviceRun device({Fault::CloseConnection, 0x08});
    auto run = device.run_policy();
    expect_only_failures(run, {"7.10.1"});
    EXPECT_EQ(find(run, "7.10.1").outcome.reason, "no answer: connection closed by peer");
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
