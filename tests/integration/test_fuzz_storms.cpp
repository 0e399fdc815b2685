// The storm ladders beyond FC 03 (connection opens, slow readers, half-open connections), each at
// rising rates with the essential-function monitor judging every rung: our own server holds at
// each; devices built to fail one storm each are found out at the rung where they give way.
#include <fmt/core.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "client/raw_link.hpp"
#include "fuzz_fragile.hpp"

namespace mblab::test {
namespace {

using ::testing::HasSubstr;

// A few cheap cases after the ladders (the storms are what is judged), a monitor every 50 ms
// within 40 ms on register 50, one-second rungs, lost for 3 s at most; the JSON report to `json`.
std::vector<std::string> laddered(const std::string& json, std::vector<std::string> ladders,
                                  const std::string& monitor = "register=50,period=50,budget=40") {
    std::vector<std::string> args = {"--class",          "quantity", "--cases",       "5",
                                     "--monitor",        monitor,    "--baseline",    "500ms",
                                     "--json",           json,       "--report-dir",  json + ".d",
                                     "--degraded-limit", "3s",       "--ladder-step", "1s"};
    for (auto& ladder : ladders) {
        args.push_back("--ladder");
        args.push_back(std::move(ladder));
    }
    return args;
}

nlohmann::json storm_summary(const std::string& json_file, const std::string& storm) {
    const auto report = nlohmann::json::parse(file_text(json_file));
    for (const auto& s : report["monitor"]["ladder"]["storms"]) {
        if (s["storm"] == storm) return s;
    }
    return nullptr;
}

TEST_F(ReferenceCliTest, OurServerHoldsTheMonitorThroughEveryStormLadder) {
    TempDir dir;
    const auto json = (dir.path() / "fuzz.json").string();
    std::vector<std::string> ladders = {"opens:20,100", "slow-readers:2,8"};
    if (client::RawLink::can_vanish()) ladders.push_back("half-open:10,50");
    auto args = laddered(json, ladders);
    args.insert(args.begin(), {"fuzz", target(), "--rate", "0"});
    auto ran = run_mblab(args);
    EXPECT_EQ(ran.status, 0) << ran.out << ran.err;
    EXPECT_THAT(ran.out, HasSubstr("storm ladder (connections opened and closed at once):\n"));
    EXPECT_THAT(ran.out, HasSubstr("the monitor held up to 100 connection opens/s [CR 7.1]"));
    EXPECT_THAT(ran.out, HasSubstr("the monitor held up to 8 slow readers/s [CR 7.1, CR 7.2]"));
    EXPECT_THAT(ran.out, HasSubstr("MONITOR VERDICT: PASS"));
    const auto report = nlohmann::json::parse(file_text(json));
    const auto& rungs = report["monitor"]["ladder"]["rungs"];
    ASSERT_EQ(rungs.size(), ladders.size() * 2);
    EXPECT_EQ(rungs[1]["storm"], "opens");
    EXPECT_GE(rungs[1]["opened"].get<int>(), 80);
    EXPECT_EQ(rungs[3]["storm"], "slow-readers");
    EXPECT_GE(rungs[3]["opened"].get<int>(), 7);
    EXPECT_GT(rungs[3]["sent"].get<int>(), 0);
    EXPECT_EQ(report["monitor"]["phases"][3]["phase"], "storm slow-readers 2/s");
    EXPECT_EQ(report["monitor"]["phases"][3]["requirement"],
              "CR 7.1 denial-of-service protection; CR 7.2 resource management");
    if (ladders.size() == 3) {
        EXPECT_THAT(ran.out, HasSubstr("the monitor held up to 50 half-open connections/s"));
        EXPECT_GE(rungs[5]["opened"].get<int>(), 40);
    }
}

// `mblab fuzz` of the reference device with `ladders` in rungs of 150 ms, `writable` the range
// the cases and the write storms may write. A rung holds three cycles: one missed on a busy
// machine is tolerated, so what is judged is the report, not the machine's load.
std::vector<std::string> short_rungs(const std::string& target, const std::string& json,
                                     std::vector<std::string> ladders, const char* writable) {
    auto args = laddered(json, std::move(ladders), "register=50,period=50,budget=40,miss=50");
    *(std::find(args.begin(), args.end(), "--ladder-step") + 1) = "150ms";
    args.insert(args.begin(), {"fuzz", target, "--rate", "0", "--writable", writable});
    return args;
}

// A request storm per function code our server serves, a short rung each: a row per code in the
// JSON report, each held; writes go to the first register and coil of the writable range that
// take a write of their own value (the monitor's register left out), the value read written back;
// FC 18 reads the FIFO the DUT file declares; FC 15, with no --allow-writes, is not run.
TEST_F(ReferenceCliTest, ARequestStormPerFunctionCodeOurServerServes) {
    TempDir dir;
    const auto json = (dir.path() / "fuzz.json").string();
    const auto dut = (dir.path() / "dut.toml").string();
    std::ofstream(dut) << "fifo_address = 0x04DE\n";
    auto args = short_rungs(target(), json, {"requests:100"}, "0:10");
    args.insert(args.end(), {"--dut", dut});
    auto ran = run_mblab(args);
    EXPECT_EQ(ran.status, 0) << ran.out << ran.err;
    EXPECT_THAT(ran.out, HasSubstr("requests per second per function code [CR 7.1]:\n"
                                   "  FC 01 read coils                       "));
    const auto report = nlohmann::json::parse(file_text(json));
    const auto& storms = report["monitor"]["ladder"]["storms"];
    const std::vector<int> codes = {0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x07, 0x08, 0x0B,
                                    0x0C, 0x0F, 0x10, 0x11, 0x14, 0x16, 0x17, 0x18, 0x2B};
    ASSERT_EQ(storms.size(), codes.size()) << storms.dump();
    for (std::size_t i = 0; i < codes.size(); ++i) {
        EXPECT_EQ(storms[i]["function"], codes[i]);
        EXPECT_EQ(storms[i]["storm"], fmt::format("fc{:02x}", codes[i]));
        EXPECT_EQ(storms[i]["requirement"], "CR 7.1");
        // The run passed, so every storm held at its one rung.
        EXPECT_EQ(storms[i]["highest_rate_held"], 100) << storms[i].dump();
    }
    const auto& not_run = report["monitor"]["ladder"]["not_run"];
    ASSERT_EQ(not_run.size(), 1U) << not_run.dump();
    EXPECT_EQ(not_run[0]["storm"], "fc15");
    EXPECT_THAT(not_run[0]["reason"].get<std::string>(), HasSubstr("only --allow-writes"));
    const auto& rungs = report["monitor"]["ladder"]["rungs"];
    ASSERT_EQ(rungs.size(), codes.size());
    EXPECT_EQ(rungs[5]["storm"], "fc06");
    EXPECT_GT(rungs[5]["sent"].get<int>(), 0);
    // Holding registers 0 to 2 of the reference profile refuse writes: passed over.
    EXPECT_EQ(rungs[5]["address"], 3);
    EXPECT_EQ(rungs[14]["storm"], "fc16");
    EXPECT_EQ(rungs[14]["address"], 3);
    EXPECT_EQ(rungs[4]["storm"], "fc05");
    EXPECT_EQ(rungs[4]["address"], 0);
    EXPECT_EQ(rungs[7]["storm"], "fc08");
    EXPECT_FALSE(rungs[7].contains("address"));
    EXPECT_EQ(rungs[13]["storm"], "fc14");
    EXPECT_GT(rungs[13]["answered"].get<int>(), 0);
    EXPECT_EQ(rungs[16]["storm"], "fc18");
    EXPECT_EQ(rungs[16]["address"], 0x04DE);
    EXPECT_GT(rungs[16]["answered"].get<int>(), 0);
}

// Without a place to write but the monitor's register, the write storms are set aside, each with
// why, and the reads run.
TEST_F(ReferenceCliTest, WriteStormsWithNowhereToWriteAreListedAsNotRun) {
    TempDir dir;
    const auto json = (dir.path() / "fuzz.json").string();
    auto ran = run_mblab(short_rungs(target(), json, {"fc06:50", "fc0f:50", "fc2b:50"}, "50:1"));
    EXPECT_EQ(ran.status, 0) << ran.out << ran.err;
    EXPECT_THAT(ran.out, HasSubstr("  FC 06 write single register            not run: no holding "
                                   "register it may write other than the monitor's register 50"));
    const auto report = nlohmann::json::parse(file_text(json));
    const auto& ladder = report["monitor"]["ladder"];
    ASSERT_EQ(ladder["not_run"].size(), 2U) << ladder.dump();
    EXPECT_EQ(ladder["not_run"][0]["storm"], "fc06");
    EXPECT_EQ(ladder["not_run"][1]["storm"], "fc0f");
    EXPECT_NE(ladder["not_run"][1]["reason"].get<std::string>().find("no coil"), std::string::npos);
    ASSERT_EQ(ladder["storms"].size(), 1U);
    EXPECT_EQ(ladder["storms"][0]["storm"], "fc2b");
}

// Each connection costs the device 10 ms: 5 opens a second leave it time for the monitor, 200 do
// not. The backlog worked through, it serves again unaided.
TEST_F(FuzzFragile, AStormOfOpensDegradesADeviceThatAcceptsSlowly) {
    start("slow-accept");
    const auto json = (dir_ / "fuzz.json").string();
    auto ran = fuzz(laddered(json, {"opens:5,200"}));
    EXPECT_EQ(ran.status, 1) << ran.out << ran.err;
    EXPECT_THAT(ran.out, HasSubstr("no finding"));
    EXPECT_THAT(ran.out, HasSubstr("the monitor held up to 5 connection opens/s, lost at 200/s"));
    EXPECT_THAT(ran.out, HasSubstr("MONITOR VERDICT: DEGRADED"));
    const auto summary = storm_summary(json, "opens");
    EXPECT_EQ(summary["highest_rate_held"], 5.0);
    EXPECT_EQ(summary["lost_at"], 200.0);
}

// One connection that never reads its answers stalls a device that sends them blocking, until
// the storm's end closes it: lost from the first rung, back unaided.
TEST_F(FuzzFragile, ASlowReaderStallsADeviceThatSendsBlocking) {
    start("blocking-send");
    const auto json = (dir_ / "fuzz.json").string();
    // The device serves reads only: the monitor reads.
    auto ran = fuzz(laddered(json, {"slow-readers:2,8"}, "read-only,period=50,budget=40"));
    EXPECT_EQ(ran.status, 1) << ran.out << ran.err;
    EXPECT_THAT(ran.out, HasSubstr("the monitor was lost from the first rung (2 slow readers/s) "
                                   "[CR 7.1, CR 7.2]"));
    EXPECT_THAT(ran.out, HasSubstr("MONITOR VERDICT: DEGRADED"));
    const auto summary = storm_summary(json, "slow-readers");
    EXPECT_TRUE(summary["highest_rate_held"].is_null());
    EXPECT_EQ(summary["lost_at"], 2.0);
}

// A device that waits on every connection it holds in turn and never times one out: two half-open
// connections a second leave it time for the monitor, forty pile up and slow it for good.
TEST_F(FuzzFragile, HalfOpenConnectionsThatPileUpFailADeviceThatPollsEachInTurn) {
    if (!client::RawLink::can_vanish()) GTEST_SKIP() << "needs CAP_NET_ADMIN (TCP_REPAIR)";
    start("polls-each");
    const auto json = (dir_ / "fuzz.json").string();
    auto ran = fuzz(laddered(json, {"half-open:2,40"}));
    EXPECT_EQ(ran.status, 1) << ran.out << ran.err;
    EXPECT_THAT(ran.out, HasSubstr("the monitor held up to 2 half-open connections/s, lost at "
                                   "40/s [CR 7.1, CR 7.2]"));
    EXPECT_THAT(
        ran.out,
        HasSubstr("MONITOR VERDICT: FAIL: the monitor did not come back without a restart"));
    const auto summary = storm_summary(json, "half-open");
    EXPECT_EQ(summary["highest_rate_held"], 2.0);
    EXPECT_EQ(summary["lost_at"], 40.0);
}

TEST(FuzzStormUsage, AnUnknownStormIsOneLineBeforeConnecting) {
    expect_usage({"fuzz", "tcp://127.0.0.1:1", "--monitor", "period=100", "--ladder", "floods:10"},
                 "mblab fuzz: --ladder 'floods:10': 'floods' is no storm (opens, slow-readers, "
                 "half-open, fc01, fc02, fc03, fc04, fc05, fc06, fc07, fc08, fc0b, fc0c, fc0f, "
                 "fc10, fc11, fc14, fc15, fc16, fc17, fc18, fc2b, or requests: every request "
                 "storm)\n");
}

TEST(FuzzStormUsage, AStormNamedTwiceIsOneLineBeforeConnecting) {
    expect_usage({"fuzz", "tcp://127.0.0.1:1", "--monitor", "period=100", "--ladder", "fc06:10",
                  "--ladder", "requests:100"},
                 "mblab fuzz: --ladder 'requests:100': the fc06 storm is already on the ladder; "
                 "give each storm once\n");
}

}  // namespace
}  // namespace mblab::test
