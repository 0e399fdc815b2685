// `conform --suite sunspec` against the built-in sunspec-inverter, over an in-memory link, and
// against devices built wrong on purpose: the shipped profile with one knob of the chain builder
// turned or one value changed. Each wrong device fails the case it is about and no other.
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "conformance/device_dut.hpp"
#include "conformance/engine.hpp"
#include "conformance/suite_selection.hpp"
#include "device/profile_loader.hpp"
#include "device/reference_device.hpp"
#include "support/manual_clock.hpp"
#include "support/memory_link.hpp"

namespace mblab::conformance {
namespace {

std::string shipped_profile() {
    std::ifstream in(std::string(MBLAB_SOURCE_DIR) + "/profiles/sunspec-inverter.toml");
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

// The shipped profile with the first `from` replaced by `to`.
std::string changed(const std::string& from, const std::string& to) {
    std::string text = shipped_profile();
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
    return text;
}

// Every case's outcome, by id.
std::map<std::string, Outcome> run_sunspec(const std::string& profile_text,
                                           protocol::Framing framing = protocol::Framing::Mbap) {
    auto profile = device::parse_profile(profile_text, "sunspec-test.toml");
    EXPECT_TRUE(profile) << profile.error();
    if (!profile) return {};
    Dut dut = dut_from_profile(*profile, "profile sunspec-test.toml");
    device::ReferenceDevice device(std::move(profile).value());
    test::ManualClock clock;
    test::MemoryDevice memory(device, framing, clock);
    client::Target target;
    target.name = "memory";
    if (framing == protocol::Framing::Mbap) {
        target.tcp = client::Endpoint{"127.0.0.1", 502, nullptr};
    } else {
        target.serial = transport::SerialUrl{};
        target.serial->kind = transport::SerialUrl::Kind::Rtu;
        dut.serial_framing = "RTU";
    }
    EngineOptions options;
    options.timeout = std::chrono::milliseconds(200);
    Session session(target, dut, options);
    session.dial_with(
        [&memory]() -> protocol::Result<std::unique_ptr<client::Link>, client::LinkError> {
            return memory.open();
        });
    std::vector<Suite> suites;
    std::string error;
    EXPECT_TRUE(
        load_suites(std::string(MBLAB_SOURCE_DIR) + "/catalogue", {"sunspec"}, suites, error))
        << error;
    Engine engine(session);
    const RunResult result = engine.run(suites, "memory");
    std::map<std::string, Outcome> outcomes;
    for (const auto& c : result.suites.at(0).cases)
        outcomes[c.id] = c.outcome;
    return outcomes;
}

constexpr const char* kLine = "sunspec.16";  // serial lines only

TEST(SunSpecSuite, TheBuiltInInverterPassesEveryCase) {
    const auto outcomes = run_sunspec(shipped_profile());
    ASSERT_EQ(outcomes.size(), 16U);
    for (const auto& [id, outcome] : outcomes) {
        EXPECT_EQ(outcome.verdict, id == kLine ? Verdict::NotApplicable : Verdict::Pass)
            << id << ": " << outcome.reason;
    }
}

// On a line the line case runs too: DA written, a broadcast write applied.
TEST(SunSpecSuite, TheBuiltInInverterPassesEveryCaseOverRtu) {
    const auto outcomes = run_sunspec(shipped_profile(), protocol::Framing::Rtu);
    ASSERT_EQ(outcomes.size(), 16U);
    for (const auto& [id, outcome] : outcomes)
        EXPECT_EQ(outcome.verdict, Verdict::Pass) << id << ": " << outcome.reason;
    EXPECT_EQ(outcomes.at(kLine).reason,
              "1.DA = 1 written; a broadcast write of 121.WMax applied, unanswered");
}

// Exception 06 asks for the request again later ([APP] 7): a device busy on every second write
// is asked again and passes; it is not judged by its busy answers.
TEST(SunSpecSuite, ABusyDeviceIsAskedAgain) {
    const auto outcomes = run_sunspec(changed("max_read_registers = 125\n",
                                              "max_read_registers = 125\n\n[[unit.faults]]\n"
                                              "action = \"exception\"\nexception = 6\n"
                                              "functions = [16]\nevery = 2\n"));
    ASSERT_EQ(outcomes.size(), 16U);
    for (const auto& [id, outcome] : outcomes) {
        EXPECT_EQ(outcome.verdict, id == kLine ? Verdict::NotApplicable : Verdict::Pass)
            << id << ": " << outcome.reason;
    }
}

struct WrongDevice {
    const char* name;
    const char* from;
    const char* to;
    const char* failing;
};

const WrongDevice kWrong[] = {
    {"marker off by one", "base = 40000", "base = 40001", "sunspec.1"},
    {"length wrong", "id = 103\n", "id = 103\nextra_registers = 2\n", "sunspec.4"},
    {"chain without end", "split_reads = \"accept\"", "split_reads = \"accept\"\nend_model = false",
     "sunspec.3"},
    {"mandatory point unimplemented", "TmpCab = 41.2\n", "", "sunspec.6"},
    {"scale factor out of range", "Tmp_SF = -1", "Tmp_SF = 11", "sunspec.8"},
    {"RW point not applied", "split_reads = \"accept\"",
     "split_reads = \"accept\"\nwrites_applied = false", "sunspec.13"},
    {"R point writable", "split_reads = \"accept\"",
     "split_reads = \"accept\"\nread_only_writable = true", "sunspec.14"},
    // A write to an R point must answer 02, 03 or 04 (SSIM 1.1), even if the value is kept.
    {"R point write acknowledged, value kept", "max_read_registers = 125",
     "max_read_registers = 125\nwrite_read_only = \"ignore\"", "sunspec.14"},
    {"R point write answered 01", "max_read_registers = 125",
     "max_read_registers = 125\nwrite_read_only = \"exception-01\"", "sunspec.14"},
};

TEST(SunSpecSuite, EachWrongDeviceFailsItsCaseAndNoOther) {
    for (const WrongDevice& wrong : kWrong) {
        SCOPED_TRACE(wrong.name);
        const auto outcomes = run_sunspec(changed(wrong.from, wrong.to));
        ASSERT_EQ(outcomes.size(), 16U);
        for (const auto& [id, outcome] : outcomes) {
            Verdict expected = Verdict::Pass;
            if (id == wrong.failing) {
                expected = Verdict::Fail;
            } else if (id == kLine || std::string(wrong.failing) == "sunspec.1") {
                // Off the bases the marker is not found: every other case is N/A.
                expected = Verdict::NotApplicable;
            }
            EXPECT_EQ(outcome.verdict, expected) << id << ": " << outcome.reason;
        }
    }
}

}  // namespace
}  // namespace mblab::conformance
