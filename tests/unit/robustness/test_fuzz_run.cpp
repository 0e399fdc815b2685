#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "device/reference_device.hpp"
#include "robustness/class_choice.hpp"
#include "robustness/fuzz_run.hpp"
#include "support/hex.hpp"
#include "support/manual_clock.hpp"
#include "support/memory_link.hpp"

// FuzzRunner and the liveness oracle against a ReferenceDevice behind memory links, on a manual
// clock: no socket, no port, no waiting.
namespace mblab::robustness {
namespace {

using namespace std::chrono_literals;
using protocol::Framing;
using test::hex;
using test::to_hex;

// Unit 1 with holding registers 0-99.
constexpr std::string_view kProfile =
    "name = \"memory\"\nunit = [{ id = 1, holding_registers = [{ start = 0, count = 100 }] }]\n";

// A reference device behind memory links of one framing, and the clock they share with the run.
struct MemoryTarget {
    explicit MemoryTarget(Framing framing) : memory(*reference, framing, clock) {}

    RunClock run_clock() {
        return {[this] { return clock.now(); },
                [this](Clock::duration span) { clock.advance(span); }};
    }
    Dial dial() {
        return [this]() -> protocol::Result<std::unique_ptr<client::Link>, client::LinkError> {
            return memory.open();
        };
    }
    FuzzOptions options() {
        FuzzOptions out;
        out.target.name = "memory";
        if (memory.framing() == Framing::Mbap) {
            out.target.tcp = client::Endpoint{};
        } else {
            out.target.serial = transport::SerialUrl{};
        }
        out.dial = dial();
        out.clock = run_clock();
        out.restart = [this] {
            memory.restart();
            return true;
        };
        return out;
    }
    Recon recon() const {
        Recon out;
        out.served = {0x03, 0x06};
        out.check_address = 5;
        return out;
    }
    FuzzResult run(FuzzOptions fuzz) {
        // Writes to registers 0-9 only: the flood's ledger has a register to write.
        const WritePolicy policy{false, WritableRange{0, 10}};
        CaseGenerator generator(recon(), policy, fuzz.seed, memory.framing(), 2ms,
                                {.connections = 50, .half_open = false});
        FuzzRunner runner(std::move(fuzz), recon(), nullptr);
        return runner.run(generator, nullptr, nullptr);
    }

    test::ManualClock clock;
    std::unique_ptr<device::ReferenceDevice> reference =
        std::move(device::load_profile_text(kProfile, "memory.toml").value());
    test::MemoryDevice memory;
};

// The oracle on the links of a memory target, asking for register 5 of unit 1.
struct OracleTarget : MemoryTarget {
    OracleTarget(Framing framing, std::chrono::milliseconds timeout)
        : MemoryTarget(framing),
          links(make_case_links(framing, dial(), {}, run_clock())),
          oracle(*links, 1, 5, timeout, run_clock()) {}

    std::unique_ptr<CaseLinks> links;
    LivenessOracle oracle;
};

// The check after the device died on whatever came next.
Liveness check_dead(OracleTarget& target) {
    target.memory.die_on([](const client::Received&) { return true; });
    auto liveness = target.oracle.check();
    EXPECT_FALSE(liveness.alive);
    return liveness;
}

// The last `count` requests the device took.
std::vector<std::string> last(const test::MemoryDevice& memory, std::size_t count) {
    const auto& all = memory.requests();
    return {all.end() - static_cast<long>(std::min(count, all.size())), all.end()};
}

TEST(LivenessOracle, AsksOnAFreshConnectionThenOnTheOneOpenedBefore) {
    OracleTarget target(Framing::Mbap, 1000ms);
    EXPECT_TRUE(target.oracle.check().alive);
    EXPECT_EQ(target.memory.requests(),
              (std::vector<std::string>{"70 01 00 00 00 06 01 03 00 05 00 01"}));
    const auto second = target.oracle.check();
    EXPECT_TRUE(second.alive) << second.reason;
    EXPECT_EQ(last(target.memory, 2),
              (std::vector<std::string>{"70 02 00 00 00 06 01 03 00 05 00 01",
                                        "70 03 00 00 00 06 01 03 00 05 00 01"}));
    // Two fresh connections and the bystander.
    EXPECT_EQ(target.memory.opened(), 3U);
    EXPECT_EQ(second.waited, 0ms);
}

TEST(LivenessOracle, ADeadDeviceIsSilentOnAFreshConnection) {
    OracleTarget target(Framing::Mbap, 1000ms);
    const auto liveness = check_dead(target);
    EXPECT_EQ(liveness.reason,
              "does not answer the known-good read (FC 03, register 5, address 1) on a fresh "
              "connection within 1000 ms");
    EXPECT_EQ(liveness.waited, 1000ms);
}

TEST(LivenessOracle, OnALineReadsPastALateAnswerThenAsksOnTheQuietLine) {
    OracleTarget target(Framing::Rtu, 300ms);
    // A case's read whose answer is still on the line when the check begins.
    client::LinkError error;
    ASSERT_TRUE(target.links->carry(0, true)->send(hex("01 03 00 00 00 01 84 0A"), error));
    const auto liveness = target.oracle.check();
    EXPECT_TRUE(liveness.alive) << liveness.reason;
    EXPECT_EQ(target.memory.requests(),
              (std::vector<std::string>{"01 03 00 00 00 01 84 0A", "01 03 00 05 00 01 94 0B"}));
    EXPECT_EQ(target.memory.opened(), 1U);
}

TEST(LivenessOracle, OnALineSilenceCountsOnceAskedTwice) {
    OracleTarget target(Framing::Rtu, 300ms);
    const auto liveness = check_dead(target);
    EXPECT_EQ(liveness.reason,
              "does not answer the known-good read (FC 03, register 5, address 1) on the link "
              "within 300 ms, asked twice");
    EXPECT_EQ(target.memory.requests(),
              (std::vector<std::string>{"01 03 00 05 00 01 94 0B", "01 03 00 05 00 01 94 0B"}));
}

TEST(FuzzRunner, AHealthyDeviceGivesNoFinding) {
    MemoryTarget target(Framing::Mbap);
    auto options = target.options();
    options.cases = 120;
    const auto result = target.run(std::move(options));
    EXPECT_TRUE(result.findings.empty()) << result.findings.front().reason;
    EXPECT_EQ(result.stopped_by, "case budget");
    EXPECT_EQ(result.cases, 120U);
    EXPECT_EQ(result.checks, 120U);
    EXPECT_GT(result.ledger.acknowledged, 0U);
}

TEST(FuzzRunner, ADeviceThatDiesOnAnUnknownFunctionIsFoundAndMinimised) {
    MemoryTarget target(Framing::Mbap);
    target.memory.die_on([](const client::Received& request) {
        return !request.pdu.empty() && request.pdu[0] == 0x41;
    });
    auto options = target.options();
    options.cases = 400;
    options.check_every = 10;
    const auto result = target.run(std::move(options));
    ASSERT_EQ(result.findings.size(), 1U);
    const auto& finding = result.findings.front();
    EXPECT_EQ(finding.kind, BadInput::UnknownFunction);
    EXPECT_EQ(finding.case_name, "FC 0x41");
    EXPECT_TRUE(finding.minimised) << finding.minimise_note;
    ASSERT_EQ(finding.reproducer.size(), 1U) << finding.minimise_note;
    // Its MBAP header, then the PDU that kills.
    EXPECT_TRUE(to_hex(finding.reproducer[0].bytes).ends_with("00 00 00 06 01 41 00 00 00 01"))
        << to_hex(finding.reproducer[0].bytes);
    EXPECT_GT(target.memory.restarts(), 1U);
    // Left running, as it was found.
    EXPECT_FALSE(target.memory.dead());
}

// With keep_going each finding is recorded, the device restarted, and the run goes on to the next.
TEST(FuzzRunner, KeepGoingRecordsEveryFindingAndRestartsAfterEach) {
    MemoryTarget target(Framing::Mbap);
    target.memory.die_on([](const client::Received& request) {
        return !request.pdu.empty() && (request.pdu[0] == 0x41 || request.pdu[0] == 0x45);
    });
    auto options = target.options();
    options.cases = 400;
    options.keep_going = true;
    const auto result = target.run(std::move(options));
    // FC 0x41, then the pipelined case that carries an FC 0x41 among its 30 requests, then FC 0x45:
    // each found on a restarted device, in the order run.
    std::vector<std::string> found;
    for (const auto& f : result.findings)
        found.push_back(f.case_name);
    EXPECT_EQ(found,
              (std::vector<std::string>{
                  "FC 0x41", "30 requests, valid, unknown and protocol id 1 in turn", "FC 0x45"}));
    EXPECT_LT(result.findings[0].case_number, result.findings[2].case_number);
    EXPECT_EQ(result.stopped_by, "case budget");
    EXPECT_EQ(result.cases, 400U);
    EXPECT_FALSE(target.memory.dead());
}

// Without a restart command a device that stays dead ends the run, findings kept.
TEST(FuzzRunner, KeepGoingStopsWhenTheDeviceDoesNotComeBack) {
    MemoryTarget target(Framing::Mbap);
    target.memory.die_on([](const client::Received& request) {
        return !request.pdu.empty() && request.pdu[0] == 0x41;
    });
    auto options = target.options();
    options.cases = 400;
    options.keep_going = true;
    options.restart = nullptr;
    options.restart_patience = 2000ms;
    const auto result = target.run(std::move(options));
    ASSERT_EQ(result.findings.size(), 1U);
    EXPECT_EQ(result.stopped_by, "finding; the device did not come back");
}

// A run of the chosen classes alone ends once their cases are done when mutations are not chosen.
TEST(FuzzRunner, TheChosenClassesAloneAndTheRunEndsWithThem) {
    MemoryTarget target(Framing::Mbap);
    auto options = target.options();
    options.cases = 100000;
    CaseGenerator generator(target.recon(), {}, 1, Framing::Mbap, 2ms,
                            {.connections = 50, .half_open = false});
    ClassChoice choice{};
    choice[static_cast<std::size_t>(BadInput::ProtocolId)] = true;
    choice[static_cast<std::size_t>(BadInput::Truncated)] = true;
    generator.choose(choice);
    FuzzRunner runner(std::move(options), target.recon(), nullptr);
    const auto result = runner.run(generator, nullptr, nullptr);
    EXPECT_EQ(result.stopped_by, "every chosen case");
    EXPECT_EQ(result.cases, generator.fixed_cases());
    EXPECT_EQ(result.classes[static_cast<std::size_t>(BadInput::ProtocolId)].run, 5U);
    EXPECT_GT(result.classes[static_cast<std::size_t>(BadInput::Truncated)].run, 0U);
    EXPECT_EQ(result.classes[static_cast<std::size_t>(BadInput::Mutation)].not_applicable,
              "not chosen (--class, --skip-class)");
    for (std::size_t i = 0; i < kBadInputCount; ++i) {
        const auto kind = static_cast<BadInput>(i);
        if (kind != BadInput::ProtocolId && kind != BadInput::Truncated) {
            EXPECT_EQ(result.classes[i].run, 0U) << class_name(kind);
        }
    }
}

TEST(FuzzRunner, OnALineOneLinkCarriesAHealthyRun) {
    MemoryTarget target(Framing::Rtu);
    auto options = target.options();
    options.cases = 100;
    const auto result = target.run(std::move(options));
    EXPECT_TRUE(result.findings.empty()) << result.findings.front().reason;
    EXPECT_EQ(result.checks, 100U);
    EXPECT_EQ(target.memory.opened(), 1U);
}

// The known-good read to address 247 with its CRC spoiled (81 9C, not 80 9D).
TEST(FuzzRunner, OnALineADeviceDeafAfterABadCrcIsMinimisedToThatFrame) {
    MemoryTarget target(Framing::Rtu);
    target.memory.die_on([](const client::Received& request) {
        return to_hex(request.bytes) == "F7 03 00 05 00 01 81 9C";
    });
    auto options = target.options();
    options.cases = 300;
    options.check_every = 10;
    const auto result = target.run(std::move(options));
    ASSERT_EQ(result.findings.size(), 1U);
    const auto& finding = result.findings.front();
    EXPECT_EQ(finding.case_name, "bad CRC to address 247 (the last unicast)");
    EXPECT_TRUE(finding.minimised) << finding.minimise_note;
    ASSERT_EQ(finding.reproducer.size(), 1U) << finding.minimise_note;
    EXPECT_EQ(to_hex(finding.reproducer[0].bytes), "F7 03 00 05 00 01 81 9C");
    EXPECT_EQ(finding.reproducer[0].connection, 0U);
}

}  // namespace
}  // namespace mblab::robustness
