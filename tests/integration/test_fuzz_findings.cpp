// `mblab fuzz` against devices that die where a fuzzer that aims only at served code would not
// look: on a reconnaissance probe, and on a malformed request for a code they do not serve.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "fuzz_fragile.hpp"

namespace mblab::test {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

// The harmless FC 17 probe (write quantity 0) kills the device: a finding, not a usage error.
TEST_F(FuzzFragile, ADeviceKilledByAProbeIsAFindingWithTheProbeAsReproducer) {
    start("probe-23");
    auto ran =
        fuzz({"--cases", "50", "--timeout", "300ms", "--json", (dir_ / "fuzz.json").string()});
    EXPECT_EQ(ran.status, 1) << ran.out << ran.err;
    EXPECT_THAT(ran.err, Not(HasSubstr("try --unit")));
    EXPECT_THAT(ran.out, HasSubstr("FINDING: the device stopped answering the known-good read"));
    EXPECT_THAT(ran.out, HasSubstr("reconnaissance probe FC 0x17"));
    const auto steps = reproducer();
    ASSERT_EQ(steps.size(), 1U) << ran.out;
    // MBAP header (transaction 1, protocol 0, length 11, unit 1), then the probe's PDU.
    EXPECT_EQ(steps[0], "00 01 00 00 00 0B 01 17 00 00 00 01 00 00 00 00 00");
    EXPECT_THAT(file_text(dir_ / "fuzz.json"), HasSubstr("reconnaissance probe FC 0x17"));

    // Its reproducer replays: a restarted device dies on it again.
    restart();
    auto replayed =
        run_mblab({"fuzz", tcp_target(port_), "--replay", (dir_ / "finding.hex").string()});
    EXPECT_EQ(replayed.status, 1) << replayed.out << replayed.err;
}

// The device answers FC 17 with exception 01, as a code it does not serve, yet parses it first and
// dies on a write quantity over 121: the malformed FC 17 is tried all the same and found.
TEST_F(FuzzFragile, AMalformedRequestForAnUnservedCodeIsTriedAndFound) {
    start("malformed-23");
    auto ran =
        fuzz({"--cases", "1500", "--timeout", "300ms", "--allow-writes", "--restart", restart_});
    EXPECT_EQ(ran.status, 1) << ran.out << ran.err;
    EXPECT_THAT(ran.out, HasSubstr("exception 01 for 01 02 04 05 06 07 08"));
    const auto steps = reproducer();
    ASSERT_EQ(steps.size(), 1U) << ran.out;
    std::vector<unsigned> bytes;
    for (std::size_t at = 0; at < steps[0].size(); at += 3)
        bytes.push_back(static_cast<unsigned>(std::stoul(steps[0].substr(at, 2), nullptr, 16)));
    ASSERT_GE(bytes.size(), 16U) << steps[0];
    EXPECT_EQ(bytes[7], 0x17U) << steps[0];
    EXPECT_GT(bytes[14] << 8 | bytes[15], 121U) << steps[0];
}

// --keep-going with the classes chosen: every protocol-id case kills the device, each is recorded
// and the device restarted; without --reproducer the findings go to a fresh directory under
// $XDG_STATE_HOME, never the current one.
TEST_F(FuzzFragile, KeepGoingRecordsEveryFindingInTheReportDirectory) {
    start("protocol-id");
    const auto state = dir_ / "state";
    const auto ran = run_program({"/usr/bin/env", "XDG_STATE_HOME=" + state.string(), MBLAB_BINARY,
                                  "fuzz", tcp_target(port_), "--rate", "0", "--keep-going",
                                  "--class", "protocol-id,mbap-length", "--skip-class",
                                  "mbap-length", "--restart", restart_});
    EXPECT_EQ(ran.status, 1) << ran.out << ran.err;
    EXPECT_THAT(ran.out, HasSubstr("5 findings (--keep-going):"));
    EXPECT_THAT(ran.out, HasSubstr("5 cases in"));
    EXPECT_THAT(ran.out, HasSubstr("(every chosen case)"));
    EXPECT_THAT(ran.out, HasSubstr("mbap-length         n/a not chosen (--class, --skip-class)"));
    std::vector<std::filesystem::path> made;
    for (const auto& entry : std::filesystem::directory_iterator(state / "mblab" / "fuzz"))
        made.push_back(entry.path());
    ASSERT_EQ(made.size(), 1U);
    EXPECT_THAT(ran.out, HasSubstr("report directory: " + made[0].string()));
    for (int n = 1; n <= 5; ++n) {
        const auto hex = made[0] / ("finding-" + std::to_string(n) + ".hex");
        EXPECT_EQ(steps_of(file_text(hex)).size(), 1U) << hex;
        EXPECT_TRUE(std::filesystem::exists(hex.string() + ".pcapng")) << hex;
    }
    const auto json = nlohmann::json::parse(file_text(made[0] / "report.json"));
    EXPECT_EQ(json["findings"].size(), 5U);
    EXPECT_EQ(json["findings"][4]["case"], "protocol id 0xFFFF");
}

TEST(FuzzClasses, AnUnknownClassIsOneLineNamingTheClasses) {
    const auto ran = run_mblab({"fuzz", "tcp://127.0.0.1:1", "--class", "floods"});
    EXPECT_EQ(ran.status, 2);
    EXPECT_THAT(ran.err, HasSubstr("mblab fuzz: --class 'floods' is not a class; the classes are "
                                   "protocol-id, mbap-length,"));
    EXPECT_EQ(std::count(ran.err.begin(), ran.err.end(), '\n'), 1);
}

}  // namespace
}  // namespace mblab::test
