// The request storms per function code without I/O: each one's request as the protocol's encoder
// writes it, where it is aimed (reads where the device answered, writes inside the write policy
// and never on the monitor's register), a write's value taken from the read before it, the codes
// not served set aside with why; the ladders `requests:RATES` makes and the ladder's progress line.
#include <fmt/core.h>
#include <gtest/gtest.h>

#include "protocol/function_table.hpp"
#include "protocol/request.hpp"
#include "robustness/fuzz_progress.hpp"
#include "robustness/ladder_run.hpp"
#include "robustness/storm_requests.hpp"
#include "support/hex.hpp"
#include "support/manual_clock.hpp"

namespace mblab::robustness {
namespace {

using namespace std::chrono_literals;
using test::hex;
using test::to_hex;

// Every request storm's request at address 7 (file 7 for the file records), writing 0x1234 (a
// coil: on; FC 16's masks keep whatever the register holds).
TEST(RequestStorms, EachRequestIsItsFunctionsWellFormedRequest) {
    const std::pair<StormKind, const char*> expected[] = {
        {StormKind::Fc01, "01 00 07 00 01"},
        {StormKind::Fc02, "02 00 07 00 01"},
        {StormKind::Fc03, "03 00 07 00 01"},
        {StormKind::Fc04, "04 00 07 00 01"},
        {StormKind::Fc05, "05 00 07 FF 00"},
        {StormKind::Fc06, "06 00 07 12 34"},
        {StormKind::Fc07, "07"},
        {StormKind::Fc08, "08 00 00 12 34"},
        {StormKind::Fc0B, "0B"},
        {StormKind::Fc0C, "0C"},
        {StormKind::Fc0F, "0F 00 07 00 01 01 01"},
        {StormKind::Fc10, "10 00 07 00 01 02 12 34"},
        {StormKind::Fc11, "11"},
        {StormKind::Fc14, "14 07 06 00 07 00 00 00 01"},
        {StormKind::Fc15, "15 09 06 00 07 00 00 00 01 12 34"},
        {StormKind::Fc16, "16 00 07 FF FF 00 00"},
        {StormKind::Fc17, "17 00 07 00 01 00 07 00 01 02 12 34"},
        {StormKind::Fc18, "18 00 07"},
        {StormKind::Fc2B, "2B 0E 01 00"},
    };
    ASSERT_EQ(request_storms().size(), std::size(expected));
    for (std::size_t i = 0; i < std::size(expected); ++i) {
        const auto [kind, bytes] = expected[i];
        EXPECT_EQ(request_storms()[i], kind);  // in the order of their codes
        const auto pdu = storm_request(kind, 7, 0x1234);
        EXPECT_EQ(to_hex(pdu), bytes) << storm_key(kind);
        // The storm's row, the function table and the decoder agree on the code.
        const auto function = storm_words(kind).function;
        EXPECT_EQ(storm_key(kind), fmt::format("fc{:02x}", function));
        const auto* row = protocol::find_function(function);
        ASSERT_NE(row, nullptr);
        if (row->request.shape == protocol::PduShape::Fixed) {
            EXPECT_EQ(pdu.size(), row->request.value) << storm_key(kind);
        }
        const auto decoded = protocol::decode_request(pdu);
        ASSERT_TRUE(decoded) << storm_key(kind);
        EXPECT_EQ(protocol::function_of(*decoded), function);
    }
    EXPECT_EQ(to_hex(storm_request(StormKind::Fc05, 7, 0)), "05 00 07 00 00");
    EXPECT_EQ(to_hex(storm_request(StormKind::Fc0F, 7, 0)), "0F 00 07 00 01 01 00");
    for (auto kind : {StormKind::Opens, StormKind::SlowReaders, StormKind::HalfOpen}) {
        EXPECT_FALSE(is_request_storm(kind));
        EXPECT_TRUE(storm_request(kind, 7, 1).empty());
    }
}

Recon served_everything() {
    Recon recon;
    recon.served = {0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x07, 0x08, 0x0B, 0x0C,
                    0x0F, 0x10, 0x11, 0x14, 0x15, 0x16, 0x17, 0x18, 0x2B};
    recon.ranges.add(Table::Coils, {3, 5});
    recon.ranges.add(Table::InputRegisters, {30, 31});
    return recon;
}

TEST(RequestStorms, ReadsAimWhereTheDeviceAnsweredAndFc03AtTheMonitorsRegister) {
    const auto recon = served_everything();
    const WritePolicy policy;  // no writes
    auto plan = plan_request_storm(StormKind::Fc01, recon, policy, 50);
    EXPECT_EQ(plan.not_run, "");
    EXPECT_EQ(to_hex(plan.pdu), "01 00 03 00 01");
    EXPECT_TRUE(plan.read_first.empty());
    // No discrete input answered with data in the reconnaissance: the usual places are asked
    // first, and the storm reads the first that answers with data, not one answering 02.
    plan = plan_request_storm(StormKind::Fc02, recon, policy, 50);
    EXPECT_TRUE(plan.pdu.empty());
    choose_place(StormKind::Fc02, plan, [](const std::vector<std::uint8_t>& pdu) {
        return hex(pdu[1] == 0 && pdu[2] == 100 ? "02 01 01" : "82 02");
    });
    EXPECT_EQ(plan.not_run, "");
    EXPECT_EQ(to_hex(plan.pdu), "02 00 64 00 01");
    plan = plan_request_storm(StormKind::Fc02, recon, policy, 50);
    choose_place(StormKind::Fc02, plan, [](const std::vector<std::uint8_t>&) {
        return std::optional<std::vector<std::uint8_t>>(hex("82 02"));
    });
    EXPECT_TRUE(plan.pdu.empty());
    EXPECT_EQ(plan.not_run,
              "no discrete input answered FC 02 with data at 0, 1, 100, 1000 or 40000");
    EXPECT_EQ(to_hex(plan_request_storm(StormKind::Fc04, recon, policy, 50).pdu), "04 00 1E 00 01");
    EXPECT_EQ(to_hex(plan_request_storm(StormKind::Fc08, recon, policy, 50).pdu), "08 00 00 12 34");
    EXPECT_EQ(to_hex(plan_request_storm(StormKind::Fc2B, recon, policy, 50).pdu), "2B 0E 01 00");
    for (auto kind : {StormKind::Fc07, StormKind::Fc0B, StormKind::Fc0C, StormKind::Fc11}) {
        EXPECT_EQ(plan_request_storm(kind, recon, policy, 50).pdu,
                  std::vector<std::uint8_t>{storm_words(kind).function});
        EXPECT_FALSE(names_address(kind));
    }
    EXPECT_EQ(to_hex(plan_request_storm(StormKind::Fc03, Recon{}, policy, 50).pdu),
              "03 00 32 00 01");
}

TEST(RequestStorms, ACodeNotServedIsNotRunWithWhy) {
    Recon recon;
    recon.not_served = {0x2B};
    recon.silent = {0x08};
    recon.not_asked = {0x06};
    const WritePolicy writable{false, WritableRange{0, 10}};
    auto plan = plan_request_storm(StormKind::Fc2B, recon, writable, 50);
    EXPECT_TRUE(plan.pdu.empty());
    EXPECT_EQ(plan.not_run, "not served: the device answered FC 2B with exception 01");
    EXPECT_EQ(plan_request_storm(StormKind::Fc08, recon, writable, 50).not_run,
              "not served: the device did not answer FC 08 in the reconnaissance");
    EXPECT_EQ(plan_request_storm(StormKind::Fc06, recon, writable, 50).not_run,
              "FC 06 writes and was not asked in the reconnaissance");
    EXPECT_EQ(plan_request_storm(StormKind::Fc04, recon, writable, 50).not_run,
              "not served: FC 04 is not among the codes the reconnaissance found");
}

TEST(RequestStorms, WritesOnlyInsideThePolicyAndNeverTheMonitorsRegister) {
    const auto recon = served_everything();
    // The writable range starts at the monitor's register: the next one is written.
    const WritePolicy writable{false, WritableRange{50, 3}};
    auto plan = plan_request_storm(StormKind::Fc06, recon, writable, 50);
    EXPECT_EQ(plan.not_run, "");
    EXPECT_EQ(plan.address, 51);
    EXPECT_EQ(to_hex(plan.read_first), "03 00 33 00 01");
    EXPECT_TRUE(plan.pdu.empty());  // until the value is read
    EXPECT_EQ(to_hex(plan_request_storm(StormKind::Fc05, recon, writable, 50).read_first),
              "01 00 33 00 01");
    // Only the monitor's register may be written, or nothing: not run.
    const WritePolicy monitor_only{false, WritableRange{50, 1}};
    EXPECT_EQ(plan_request_storm(StormKind::Fc10, recon, monitor_only, 50).not_run,
              "no holding register it may write other than the monitor's register 50: "
              "--writable START:COUNT (outside it) or --allow-writes lets it write one back");
    EXPECT_NE(plan_request_storm(StormKind::Fc17, recon, WritePolicy{}, 50)
                  .not_run.find("FC 17 has no read-only form"),
              std::string::npos);
    EXPECT_NE(plan_request_storm(StormKind::Fc0F, recon, WritePolicy{}, 50).not_run, "");
    // Writes allowed anywhere: where the reconnaissance was answered, past the monitor's.
    Recon answered = recon;
    answered.ranges.add(Table::HoldingRegisters, {50, 60});
    EXPECT_EQ(plan_request_storm(StormKind::Fc06, answered, WritePolicy{true, {}}, 50).address, 51);
    EXPECT_EQ(plan_request_storm(StormKind::Fc05, answered, WritePolicy{true, {}}, 50).address, 3);
    Recon just_the_monitor = recon;
    just_the_monitor.ranges.add(Table::HoldingRegisters, {50, 50});
    EXPECT_NE(
        plan_request_storm(StormKind::Fc06, just_the_monitor, WritePolicy{true, {}}, 50).not_run,
        "");
}

TEST(RequestStorms, AWriteWritesBackTheValueReadBeforeIt) {
    const auto recon = served_everything();
    const WritePolicy writable{false, WritableRange{50, 3}};
    const auto written = [&](StormKind kind, const char* answer) {
        auto plan = plan_request_storm(kind, recon, writable, 50);
        write_back(kind, plan, hex(answer));
        return plan.not_run.empty() ? to_hex(plan.pdu) : plan.not_run;
    };
    EXPECT_EQ(written(StormKind::Fc06, "03 02 AB CD"), "06 00 33 AB CD");
    EXPECT_EQ(written(StormKind::Fc10, "03 02 AB CD"), "10 00 33 00 01 02 AB CD");
    EXPECT_EQ(written(StormKind::Fc17, "03 02 AB CD"), "17 00 33 00 01 00 33 00 01 02 AB CD");
    EXPECT_EQ(written(StormKind::Fc05, "01 01 01"), "05 00 33 FF 00");
    EXPECT_EQ(written(StormKind::Fc05, "01 01 00"), "05 00 33 00 00");
    EXPECT_EQ(written(StormKind::Fc0F, "01 01 01"), "0F 00 33 00 01 01 01");
    EXPECT_EQ(written(StormKind::Fc06, "83 02"),
              "holding register 51 does not answer FC 03: no value to write back");
    EXPECT_EQ(written(StormKind::Fc05, "03 02 00 01"),
              "coil 51 does not answer FC 01: no value to write back");
    auto plan = plan_request_storm(StormKind::Fc06, recon, writable, 50);
    write_back(StormKind::Fc06, plan, std::nullopt);
    EXPECT_EQ(plan.not_run, "holding register 51 does not answer FC 03: no value to write back");
    // A read is left as it is.
    plan = plan_request_storm(StormKind::Fc01, recon, writable, 50);
    write_back(StormKind::Fc01, plan, hex("81 01"));
    EXPECT_EQ(to_hex(plan.pdu), "01 00 03 00 01");
}

// A device whose registers 51 and 52 refuse writes (02) and whose 53 takes them: the storm writes
// 53, its own value, after one write back of it proved the place.
TEST(RequestStorms, AWriteGoesToTheFirstPlaceThatTakesAWriteOfItsOwnValue) {
    const auto recon = served_everything();
    auto plan = plan_request_storm(StormKind::Fc06, recon, WritePolicy{false, {{50, 5}}}, 50);
    EXPECT_EQ(plan.places, (std::vector<std::uint16_t>{51, 52, 53, 54}));
    std::vector<std::string> asked;
    const StormAsk device = [&](const std::vector<std::uint8_t>& pdu) {
        asked.push_back(to_hex(pdu));
        const std::uint16_t address = static_cast<std::uint16_t>(pdu[1] << 8 | pdu[2]);
        if (pdu[0] == 0x03) return hex(fmt::format("03 02 00 {:02X}", address));
        if (address < 53) return hex("86 02");
        return pdu;  // the echo
    };
    choose_write_place(StormKind::Fc06, plan, device);
    EXPECT_EQ(plan.not_run, "");
    EXPECT_EQ(plan.address, 53);
    EXPECT_EQ(to_hex(plan.pdu), "06 00 35 00 35");
    EXPECT_EQ(asked,
              (std::vector<std::string>{"03 00 33 00 01", "06 00 33 00 33", "03 00 34 00 01",
                                        "06 00 34 00 34", "03 00 35 00 01", "06 00 35 00 35"}));
    // None takes it: not run, with the last place's reason.
    plan = plan_request_storm(StormKind::Fc06, recon, WritePolicy{false, {{50, 3}}}, 50);
    choose_write_place(StormKind::Fc06, plan, device);
    EXPECT_TRUE(plan.pdu.empty());
    EXPECT_EQ(plan.not_run,
              "none of the 2 places tried takes a write back; the last: holding register 52 "
              "refused the write of its own value (exception 02)");
    plan = plan_request_storm(StormKind::Fc05, recon, WritePolicy{false, {{50, 2}}}, 50);
    choose_write_place(StormKind::Fc05, plan, [](const std::vector<std::uint8_t>&) {
        return std::optional<std::vector<std::uint8_t>>();
    });
    EXPECT_EQ(plan.not_run, "coil 51 does not answer FC 01: no value to write back");
}

// A file or a FIFO is found by asking: the DUT file's first, then the usual places, the first
// answered with data taken; none answered is not run, with the places tried.
TEST(RequestStorms, FileAndFifoReadsGoWhereTheDeviceAnsweredData) {
    auto recon = served_everything();
    auto plan = plan_request_storm(StormKind::Fc14, recon, WritePolicy{}, 50);
    EXPECT_EQ(plan.not_run, "");
    EXPECT_TRUE(plan.pdu.empty());  // until a file answers
    EXPECT_EQ(plan.places, (std::vector<std::uint16_t>{1, 2, 3, 4}));
    recon.file_number = 3;
    recon.fifo_address = 0x04DE;
    EXPECT_EQ(plan_request_storm(StormKind::Fc14, recon, WritePolicy{}, 50).places,
              (std::vector<std::uint16_t>{3, 1, 2, 4}));
    plan = plan_request_storm(StormKind::Fc18, recon, WritePolicy{}, 50);
    EXPECT_EQ(plan.places, (std::vector<std::uint16_t>{0x04DE, 0, 1, 100, 1000, 40000}));
    std::vector<std::string> asked;
    // Only FIFO 100 and file 2 answer with data.
    const StormAsk device = [&](const std::vector<std::uint8_t>& pdu) {
        asked.push_back(to_hex(pdu));
        if (to_hex(pdu) == "18 00 64") return hex("18 00 04 00 01 00 07");
        if (to_hex(pdu) == "14 07 06 00 02 00 00 00 01") return hex("14 04 03 06 00 09");
        return hex(fmt::format("{:02X} 02", pdu[0] | 0x80));
    };
    choose_place(StormKind::Fc18, plan, device);
    EXPECT_EQ(plan.not_run, "");
    EXPECT_EQ(plan.address, 100);
    EXPECT_EQ(to_hex(plan.pdu), "18 00 64");
    EXPECT_EQ(asked, (std::vector<std::string>{"18 04 DE", "18 00 00", "18 00 01", "18 00 64"}));
    EXPECT_TRUE(names_address(StormKind::Fc18));
    EXPECT_FALSE(names_address(StormKind::Fc14));
    plan = plan_request_storm(StormKind::Fc14, served_everything(), WritePolicy{}, 50);
    choose_place(StormKind::Fc14, plan, device);
    EXPECT_EQ(to_hex(plan.pdu), "14 07 06 00 02 00 00 00 01");
    plan = plan_request_storm(StormKind::Fc18, served_everything(), WritePolicy{}, 50);
    choose_place(StormKind::Fc18, plan, [](const std::vector<std::uint8_t>&) {
        return std::optional<std::vector<std::uint8_t>>(hex("98 02"));
    });
    EXPECT_TRUE(plan.pdu.empty());
    EXPECT_EQ(plan.not_run,
              "no FIFO answered FC 18 with data at 0, 1, 100, 1000 or 40000 (a DUT file's "
              "fifo_address names one: --dut)");
    plan = plan_request_storm(StormKind::Fc14, served_everything(), WritePolicy{}, 50);
    choose_place(StormKind::Fc14, plan, [](const std::vector<std::uint8_t>&) {
        return std::optional<std::vector<std::uint8_t>>();
    });
    EXPECT_EQ(plan.not_run,
              "no file answered FC 14 with data at 1, 2, 3 or 4 (a DUT file's file_number names "
              "one: --dut)");
}

// FC 16 with AND FFFF, OR 0000 and FC 15 with the record read by FC 14 write back what is there;
// both only where the policy lets a write go, FC 15 only with --allow-writes.
TEST(RequestStorms, MaskAndFileRecordWritesLeaveTheValueAsItWas) {
    const auto recon = served_everything();
    const WritePolicy writable{false, WritableRange{50, 3}};
    auto plan = plan_request_storm(StormKind::Fc16, recon, writable, 50);
    EXPECT_EQ(plan.address, 51);
    EXPECT_EQ(to_hex(plan.read_first), "03 00 33 00 01");
    write_back(StormKind::Fc16, plan, hex("03 02 AB CD"));
    EXPECT_EQ(to_hex(plan.pdu), "16 00 33 FF FF 00 00");
    EXPECT_EQ(plan_request_storm(StormKind::Fc16, recon, WritePolicy{false, {{50, 1}}}, 50).not_run,
              "no holding register it may write other than the monitor's register 50: "
              "--writable START:COUNT (outside it) or --allow-writes lets it write one back");
    EXPECT_EQ(plan_request_storm(StormKind::Fc15, recon, writable, 50).not_run,
              "file records lie outside --writable (holding registers): only --allow-writes lets "
              "FC 15 write one back");
    plan = plan_request_storm(StormKind::Fc15, recon, WritePolicy{true, {}}, 50);
    EXPECT_EQ(plan.not_run, "");
    EXPECT_EQ(plan.address, 1);
    EXPECT_EQ(to_hex(plan.read_first), "14 07 06 00 01 00 00 00 01");
    auto failed = plan;
    write_back(StormKind::Fc15, plan, hex("14 04 03 06 AB CD"));
    EXPECT_EQ(to_hex(plan.pdu), "15 09 06 00 01 00 00 00 01 AB CD");
    write_back(StormKind::Fc15, failed, hex("94 02"));
    EXPECT_EQ(failed.not_run, "file 1 does not answer FC 14: no value to write back");
    // File 1 refuses the write, file 2 takes it: the storm writes file 2's own value.
    plan = plan_request_storm(StormKind::Fc15, recon, WritePolicy{true, {}}, 50);
    choose_place(StormKind::Fc15, plan, [](const std::vector<std::uint8_t>& pdu) {
        if (pdu[0] == 0x14) return hex(fmt::format("14 04 03 06 00 {:02X}", pdu[4]));
        return pdu[4] == 1 ? hex("95 04") : pdu;
    });
    EXPECT_EQ(plan.not_run, "");
    EXPECT_EQ(plan.address, 2);
    EXPECT_EQ(to_hex(plan.pdu), "15 09 06 00 02 00 00 00 01 00 02");
}

TEST(RequestStorms, AWriteStormStreamsLikeFc03OnAManualClock) {
    test::ManualClock clock;
    StormCore core(StormKind::Fc06, 200, clock.now(), 1000ms);
    auto actions = core.poll(clock.now());
    ASSERT_EQ(actions.size(), 1U);
    EXPECT_EQ(actions[0].what, StormAction::Do::OpenStream);
    core.opened(true);
    clock.advance(25ms);
    actions = core.poll(clock.now());
    ASSERT_EQ(actions.size(), 1U);
    EXPECT_EQ(actions[0].what, StormAction::Do::SendRequests);
    EXPECT_EQ(actions[0].count, 5U);
    EXPECT_EQ(storm_phase_name(StormKind::Fc06, 200), "storm fc06 200/s");
    EXPECT_EQ(storm_heading(StormKind::Fc2B),
              "FC 2B (encapsulated interface transport) MEI 0E (read device identification), "
              "basic objects, answers never waited for");
}

// One verdict per storm: a storm named twice, by its key or through `requests`, is refused; a
// bare rate list is FC 03's.
TEST(RequestStorms, AStormNamedTwiceIsRefused) {
    using Texts = std::vector<std::string>;
    const auto both = parse_ladders(Texts{"fc06:10", "opens:5,50"});
    ASSERT_TRUE(both);
    ASSERT_EQ(both->size(), 2U);
    EXPECT_EQ((*both)[1].kind, StormKind::Opens);
    EXPECT_EQ(parse_ladders(Texts{"fc06:10", "fc06:20"}).error(),
              "--ladder 'fc06:20': the fc06 storm is already on the ladder; give each storm once");
    EXPECT_EQ(parse_ladders(Texts{"fc06:10", "requests:100"}).error(),
              "--ladder 'requests:100': the fc06 storm is already on the ladder; give each "
              "storm once");
    EXPECT_EQ(parse_ladders(Texts{"100", "fc03:200"}).error(),
              "--ladder 'fc03:200': the fc03 storm is already on the ladder; give each storm "
              "once");
}

TEST(RequestStorms, RequestsMakesALadderPerCodeAndTheUnservedAreSetAside) {
    const auto ladders = parse_ladders("requests:100,500");
    ASSERT_TRUE(ladders);
    ASSERT_EQ(ladders->size(), request_storms().size());
    EXPECT_EQ((*ladders)[0].kind, StormKind::Fc01);
    EXPECT_EQ((*ladders)[18].kind, StormKind::Fc2B);
    EXPECT_EQ((*ladders)[18].rates, (std::vector<double>{100, 500}));
    EXPECT_EQ(parse_ladders("fc0f:10")->at(0).kind, StormKind::Fc0F);
    EXPECT_EQ(parse_ladders("100")->at(0).kind, StormKind::Fc03);
    EXPECT_EQ(parse_ladders("requests:5,1").error(),
              "--ladder 'requests:5,1': give rising rates per second, e.g. 100,500,1000");
    EXPECT_EQ(parse_ladders("fc15:10")->at(0).kind, StormKind::Fc15);
    EXPECT_EQ(parse_ladders("fc5b:10").error(),
              "--ladder 'fc5b:10': 'fc5b' is no storm (opens, slow-readers, half-open, fc01, "
              "fc02, fc03, fc04, fc05, fc06, fc07, fc08, fc0b, fc0c, fc0f, fc10, fc11, fc14, "
              "fc15, fc16, fc17, fc18, fc2b, or requests: every request storm)");
    Recon recon;
    recon.served = {0x01, 0x03, 0x06};
    const auto planned = plan_ladders({{StormKind::Fc01, {100, 500}},
                                       {StormKind::Fc06, {100}},
                                       {StormKind::Fc2B, {100}},
                                       {StormKind::Opens, {10, 20}}},
                                      recon, WritePolicy{}, 0);
    ASSERT_EQ(planned.size(), 4U);
    EXPECT_EQ(planned[0].request.not_run, "");
    EXPECT_NE(planned[1].request.not_run, "");  // nowhere to write
    EXPECT_NE(planned[2].request.not_run, "");  // not served
    EXPECT_TRUE(planned[3].request.pdu.empty());
    EXPECT_EQ(rungs_to_run(planned), 4U);
}

TEST(RequestStorms, TheLaddersProgressLineCountsTheRungsLeft) {
    EXPECT_EQ(ladder_progress_text(0, 4, 2000ms, "storm fc01 100/s"),
              "rung 1/4, about 8s left in the ladder: storm fc01 100/s");
    EXPECT_EQ(ladder_progress_text(3, 4, 500ms, "storm fc2b 500/s"),
              "rung 4/4, about 1s left in the ladder: storm fc2b 500/s");
    EXPECT_EQ(ladder_progress_text(0, 40, 2000ms, "storm fc01 100/s"),
              "rung 1/40, about 1m 20s left in the ladder: storm fc01 100/s");
}

}  // namespace
}  // namespace mblab::robustness
