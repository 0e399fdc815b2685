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
#include "conformance/sunspec_probe.hpp"
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

// A device loaded from `profile_text` behind an in-memory link, and a session to it.
struct MemorySunSpec {
    explicit MemorySunSpec(const std::string& profile_text,
                           protocol::Framing framing = protocol::Framing::Mbap)
        : profile(load(profile_text)),
          dut(dut_from_profile(profile, "profile sunspec-test.toml")),
          device(profile),
          memory(device, framing, clock),
          session(target_for(framing, dut), dut, engine_options()) {
        session.dial_with(
            [this]() -> protocol::Result<std::unique_ptr<client::Link>, client::LinkError> {
                return memory.open();
            });
    }

    static device::Profile load(const std::string& text) {
        auto parsed = device::parse_profile(text, "sunspec-test.toml");
        EXPECT_TRUE(parsed) << parsed.error();
        return parsed ? std::move(parsed).value() : device::Profile{};
    }
    static client::Target target_for(protocol::Framing framing, Dut& dut) {
        client::Target target;
        target.name = "memory";
        if (framing == protocol::Framing::Mbap) {
            target.tcp = client::Endpoint{"127.0.0.1", 502, nullptr};
        } else {
            target.serial = transport::SerialUrl{};
            target.serial->kind = transport::SerialUrl::Kind::Rtu;
            dut.serial_framing = "RTU";
        }
        return target;
    }
    static EngineOptions engine_options() {
        EngineOptions options;
        options.timeout = std::chrono::milliseconds(200);
        return options;
    }

    device::Profile profile;
    Dut dut;
    device::ReferenceDevice device;
    test::ManualClock clock;
    test::MemoryDevice memory;
    Session session;
};

// Every case's outcome, by id.
std::map<std::string, Outcome> run_sunspec(const std::string& profile_text,
                                           protocol::Framing framing = protocol::Framing::Mbap) {
    MemorySunSpec lab(profile_text, framing);
    std::vector<Suite> suites;
    std::string error;
    EXPECT_TRUE(
        load_suites(std::string(MBLAB_SOURCE_DIR) + "/catalogue", {"sunspec"}, suites, error))
        << error;
    Engine engine(lab.session);
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

// The probe's reads and writes go through the codec: registers past 0xFFFF are refused rather
// than sent cut to 16 bits, and a write is judged by its echo.
TEST(SunSpecProbe, ReadsAndWritesStayInsideTheRegisterAddresses) {
    MemorySunSpec lab(shipped_profile());
    SunSpecProbe probe(lab.session);
    ASSERT_FALSE(probe.unusable()) << probe.unusable()->reason;

    const auto marker = probe.read(40000, 2);
    ASSERT_TRUE(marker) << marker.error().message;
    EXPECT_EQ(*marker, (std::vector<std::uint16_t>{0x5375, 0x6E53}));  // "SunS"

    const auto past = probe.read(0xFFFF, 2);
    ASSERT_FALSE(past);
    EXPECT_EQ(past.error().kind, client::ErrorKind::Invalid);
    EXPECT_EQ(past.error().message, "registers 65535 to 65536 run past the last address, 65535");

    const std::vector<std::uint16_t> too_many(124, 0);
    const auto refused = probe.write(40000, too_many);
    ASSERT_FALSE(refused);
    EXPECT_EQ(refused.error().message, "124 registers do not fit one write (at most 123)");
}

}  // namespace
}  // namespace mblab::conformance
