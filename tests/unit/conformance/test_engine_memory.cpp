// A whole conformance run, the real Engine and Session, against the reference device behind
// in-memory links on a manual clock: the policy suite over Modbus/TCP and over RTU, and a
// device that breaks one function failing exactly the cases of that function.
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "conformance/device_dut.hpp"
#include "conformance/engine.hpp"
#include "conformance/suite_selection.hpp"
#include "device/profile_loader.hpp"
#include "device/reference_device.hpp"
#include "support/manual_clock.hpp"
#include "support/memory_link.hpp"
#include "support/rewriting_handler.hpp"

namespace mblab::conformance {
namespace {

using protocol::Framing;

const std::string kCatalogue = std::string(MBLAB_SOURCE_DIR) + "/catalogue";
const std::string kProfile = std::string(MBLAB_SOURCE_DIR) + "/profiles/reference.toml";

std::vector<Suite> shipped_suite(const std::string& name = "policy-2.1") {
    std::vector<Suite> suites;
    std::string error;
    EXPECT_TRUE(load_suites(kCatalogue, {name}, suites, error)) << error;
    return suites;
}

// Answers FC 03 with exception 04 (server device failure) and leaves the rest to the device.
std::optional<std::vector<std::uint8_t>> broken_read(std::span<const std::uint8_t> request) {
    if (request.empty() || request[0] != 0x03) return std::nullopt;
    return std::vector<std::uint8_t>{0x83, 0x04};
}

struct MemoryRun {
    explicit MemoryRun(Framing framing, bool broken_reads = false)
        : broken(*device, broken_read),
          memory(broken_reads ? static_cast<device::RequestHandler&>(broken)
                              : static_cast<device::RequestHandler&>(*device),
                 framing, clock) {}

    RunResult run(const std::string& suite = "policy-2.1") {
        auto profile = device::read_profile(kProfile);
        EXPECT_TRUE(profile) << profile.error();
        const Dut dut = dut_from_profile(*profile, "profile reference.toml");
        client::Target target;
        target.name = "memory";
        if (memory.framing() == Framing::Mbap) {
            target.tcp = client::Endpoint{"127.0.0.1", 502, nullptr};
        } else {
            target.serial = transport::SerialUrl{};
            target.serial->kind = transport::SerialUrl::Kind::Rtu;
        }
        EngineOptions options;
        options.timeout = std::chrono::milliseconds(200);
        Session session(target, dut, options);
        session.dial_with(
            [this]() -> protocol::Result<std::unique_ptr<client::Link>, client::LinkError> {
                return memory.open();
            });
        client::LinkError error;
        EXPECT_TRUE(session.connect(error)) << error.message;
        Engine engine(session);
        return engine.run(shipped_suite(suite), "memory");
    }

    test::ManualClock clock;
    std::unique_ptr<device::ReferenceDevice> device =
        std::move(device::load_profile(kProfile).value());
    test::RewritingHandler broken;
    test::MemoryDevice memory;
};

std::vector<std::string> failed_ids(const RunResult& result) {
    std::vector<std::string> ids;
    for (const auto& suite : result.suites) {
        for (const auto& c : suite.cases) {
            if (c.outcome.verdict == Verdict::Fail) ids.push_back(c.id + ": " + c.outcome.reason);
        }
    }
    return ids;
}

TEST(EngineInMemory, TheReferenceDevicePassesThePolicySuiteOverModbusTcp) {
    MemoryRun run(Framing::Mbap);
    const auto result = run.run();
    const auto counts = result.counts();
    EXPECT_GE(counts.passed, 15U);
    EXPECT_EQ(counts.not_run, 0U);
    // 9.1.3 sends a header whose length runs past the bytes sent: the real server answers 03
    // when its partial-frame timer runs out (MbapSession's trace tests), while the memory
    // device, which has no such timer, closes. Every other case passes.
    const std::vector<std::string> expected{
        "9.1.3: no answer from unit 1: closed by the device (request 1 on this connection)"};
    EXPECT_EQ(failed_ids(result), expected);
    EXPECT_FALSE(run.memory.requests().empty());
}

// The serial suite's cases that read answers back depend on ser.7; over Modbus/TCP none of them
// applies, and each says so (N/A) rather than that ser.7 did not pass (NOT RUN).
TEST(EngineInMemory, ACaseThatDoesNotApplyIsNotApplicableWhateverItDependsOn) {
    MemoryRun run(Framing::Mbap);
    const auto result = run.run("serial");
    ASSERT_EQ(result.suites.size(), 1U);
    EXPECT_EQ(result.counts().not_run, 0U);
    for (const auto& c : result.suites[0].cases)
        EXPECT_EQ(c.outcome.verdict, Verdict::NotApplicable) << c.id << ": " << c.outcome.reason;
}

TEST(EngineInMemory, TheReferenceDevicePassesThePolicySuiteOverRtu) {
    MemoryRun run(Framing::Rtu);
    const auto result = run.run();
    EXPECT_GE(result.counts().passed, 15U);
    EXPECT_TRUE(failed_ids(result).empty()) << ::testing::PrintToString(failed_ids(result));
    // Every request went out as an RTU frame to unit 1: address first, never an MBAP header.
    for (const auto& request : run.memory.requests())
        EXPECT_EQ(request.rfind("01 ", 0), 0U) << request;
}

TEST(EngineInMemory, ADeviceThatFailsEveryReadFailsTheReadCasesWithTheException) {
    MemoryRun run(Framing::Mbap, true);
    const auto result = run.run();
    const auto failed = failed_ids(result);
    ASSERT_FALSE(failed.empty());
    const auto names_exception_04 = [](const std::string& line) {
        return line.find("04") != std::string::npos;
    };
    EXPECT_TRUE(std::any_of(failed.begin(), failed.end(), names_exception_04))
        << ::testing::PrintToString(failed);
    // Only the cases that read registers are hit: fewer pass than on the sound device.
    MemoryRun sound(Framing::Mbap);
    EXPECT_LT(result.counts().passed, sound.run().counts().passed);
}

}  // namespace
}  // namespace mblab::conformance
