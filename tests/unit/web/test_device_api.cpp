// The REST API of serve --http as calls in, JSON out, checked against what Modbus then answers.
#include <gtest/gtest.h>

#include <array>
#include <map>

#include "server/traffic_log.hpp"
#include "web_harness.hpp"

namespace mblab::test {
namespace {

TEST(DeviceApi, WritesRegistersThatModbusThenReads) {
    WebHarness h;
    auto reply = h.call("PUT", "/api/units/1/holding_registers/10", R"({"values":[4660,22136]})");
    EXPECT_EQ(reply.status, 200) << reply.body;
    EXPECT_EQ(h.ask("03 00 0A 00 02"), "03 04 12 34 56 78");
    reply = h.call("GET", "/api/units/1/holding_registers", "", {{"start", "9"}, {"count", "3"}});
    EXPECT_EQ(reply.status, 200);
    EXPECT_EQ(h.json(reply)["values"], nlohmann::json::parse("[0,4660,22136]"));
}

TEST(DeviceApi, WritesInputsModbusCannotWrite) {
    WebHarness h;
    EXPECT_EQ(h.call("PUT", "/api/units/1/input_registers/0", R"({"values":[7]})").status, 200);
    EXPECT_EQ(h.ask("04 00 00 00 01"), "04 02 00 07");
    EXPECT_EQ(h.call("PUT", "/api/units/1/coils/3", R"({"values":[1,1]})").status, 200);
    EXPECT_EQ(h.ask("01 00 00 00 08"), "01 01 18");
}

TEST(DeviceApi, ModbusWritesShowInTheApi) {
    WebHarness h;
    EXPECT_EQ(h.ask("10 00 00 00 02 04 00 01 00 02"), "10 00 00 00 02");
    auto reply = h.call("GET", "/api/units/1/holding_registers", "", {{"count", "2"}});
    EXPECT_EQ(h.json(reply)["values"], nlohmann::json::parse("[1,2]"));
}

TEST(DeviceApi, HolesReadAsNullAndAWriteOverOneChangesNothing) {
    WebHarness h;
    auto reply =
        h.call("GET", "/api/units/1/holding_registers", "", {{"start", "99"}, {"count", "2"}});
    EXPECT_EQ(h.json(reply)["values"], nlohmann::json::parse("[0,null]"));
    reply = h.call("PUT", "/api/units/1/holding_registers/99", R"({"values":[5,5]})");
    EXPECT_EQ(reply.status, 409);
    EXPECT_EQ(reply.body,
              R"({"error":"unit 1 holding_registers 99..100: not every address is mapped"})");
    EXPECT_EQ(h.ask("03 00 63 00 01"), "03 02 00 00");
}

// A SunSpec chain's registers are named by model and point, so the API lists them by name.
TEST(DeviceApi, SunSpecPointsAreListedByName) {
    WebHarness h(R"(
[[unit]]
id = 1
[unit.sunspec]
[[unit.sunspec.model]]
id = 1
points = { Mn = "m", Md = "d", SN = "1" }
[[unit.sunspec.model]]
id = 103
points = { W_SF = 1, W = 8500 }
)");
    const auto units = h.json(h.call("GET", "/api/units"));
    std::map<std::string, std::uint32_t> starts;
    for (const auto& range : units[0]["banks"]["holding_registers"])
        starts[range["name"].get<std::string>()] = range["start"].get<std::uint32_t>();
    EXPECT_EQ(starts["SunS"], 40000U);
    EXPECT_EQ(starts["1.Mn"], 40004U);
    EXPECT_EQ(starts["103.W"], 40084U);
    EXPECT_EQ(starts["end"], 40122U);
    const auto reply =
        h.call("GET", "/api/units/1/holding_registers", "", {{"start", "40084"}, {"count", "2"}});
    EXPECT_EQ(h.json(reply)["values"], nlohmann::json::parse("[850,1]"));
}

TEST(DeviceApi, BadRequestsGetOneLineReasons) {
    WebHarness h;
    const auto error = [&](const web::ApiReply& reply) {
        return std::to_string(reply.status) + " " + h.json(reply).value("error", "");
    };
    EXPECT_EQ(error(h.call("PUT", "/api/units/1/holding_registers/0", "{values:")),
              "400 the body is not valid JSON");
    EXPECT_EQ(error(h.call("PUT", "/api/units/1/holding_registers/0", R"({"values":[65536]})")),
              "400 values: holding_registers takes integers from 0 to 65535");
    EXPECT_EQ(error(h.call("PUT", "/api/units/1/coils/0", R"({"values":[2]})")),
              "400 values: coils takes integers from 0 to 1");
    EXPECT_EQ(error(h.call("PUT", "/api/units/1/coils/0", R"([1])")),
              "400 expected {\"values\": [...]} with 1 to 2000 values");
    EXPECT_EQ(error(h.call("GET", "/api/units/9/coils")), "404 unit 9: no such unit (units: 1,2)");
    EXPECT_EQ(error(h.call("GET", "/api/units/x/coils")), "404 unit x: no such unit (units: 1,2)");
    EXPECT_EQ(error(h.call("GET", "/api/units/1/holding", "")),
              "404 holding: no such bank (coils, discrete_inputs, holding_registers, "
              "input_registers, faults)");
    EXPECT_EQ(error(h.call("GET", "/api/units/1/coils", "", {{"start", "65535"}, {"count", "2"}})),
              "400 start 65535 + count 2 runs past address 65535");
    EXPECT_EQ(error(h.call("GET", "/api/units/1/coils", "", {{"start", "-1"}})),
              "400 start: expected an address from 0 to 65535");
    EXPECT_EQ(error(h.call("GET", "/api/units/1/coils", "", {{"count", "0"}})),
              "400 count: expected 1 to 2000");
    EXPECT_EQ(error(h.call("PUT", "/api/units/1/holding_registers/65536", R"({"values":[1]})")),
              "400 65536: expected an address from 0 to 65535");
    EXPECT_EQ(error(h.call("DELETE", "/api/counters")), "405 /api/counters takes GET, not DELETE");
    EXPECT_EQ(error(h.call("GET", "/api/nothing")), "404 no such resource: GET /api/nothing");
    EXPECT_EQ(error(h.call("POST", "/api/state/save")),
              "409 serve runs without --state FILE: nothing to save to");
}

TEST(DeviceApi, FaultRulesAreListedAddedSwitchedAndRemoved) {
    WebHarness h;
    EXPECT_EQ(h.ask("06 00 00 00 01"), "86 06");
    auto reply = h.call("GET", "/api/units/1/faults");
    EXPECT_EQ(reply.body,
              R"([{"action":"exception","enabled":true,"exception":6,"functions":[6],"index":0,)"
              R"("probability":1.0}])");

    reply = h.call("POST", "/api/units/1/faults",
                   R"({"action":"exception","exception":4,"functions":[3],"addresses":[5,9]})");
    EXPECT_EQ(reply.status, 201) << reply.body;
    EXPECT_EQ(h.ask("03 00 00 00 01"), "03 02 00 00");
    EXPECT_EQ(h.ask("03 00 05 00 01"), "83 04");

    reply = h.call("PUT", "/api/units/1/faults/1",
                   R"({"action":"exception","exception":4,"functions":[3],"enabled":false})");
    EXPECT_EQ(reply.status, 200) << reply.body;
    EXPECT_EQ(h.ask("03 00 05 00 01"), "03 02 00 00");
    EXPECT_EQ(h.json(reply)[1]["enabled"], false);

    EXPECT_EQ(h.call("DELETE", "/api/units/1/faults/0").status, 200);
    EXPECT_EQ(h.ask("06 00 00 00 01"), "06 00 00 00 01");
    EXPECT_EQ(h.json(h.call("GET", "/api/units/1/faults")).size(), 1U);
    EXPECT_EQ(h.call("DELETE", "/api/units/1/faults/5").status, 404);
    // Unit 2 has rules of its own.
    EXPECT_EQ(h.call("GET", "/api/units/2/faults").body, "[]");
}

TEST(DeviceApi, BadFaultRulesAreRefusedWithTheField) {
    WebHarness h;
    const auto error = [&](const std::string& body) {
        return h.json(h.call("POST", "/api/units/1/faults", body)).value("error", "");
    };
    EXPECT_EQ(error(R"({"action":"explode"})"),
              "action: expected one of delay, drop, exception, garbage, close, got \"explode\"");
    EXPECT_EQ(error(R"({"action":"delay"})"),
              "delay_ms: missing key; a delay rule needs it: how long to hold the answer, in "
              "milliseconds");
    EXPECT_EQ(error(R"({"action":"drop","functions":[200]})"),
              "functions[0]: expected an integer from 1 to 127, got 200");
    EXPECT_EQ(error(R"({"action":"drop","every":2,"probability":0.5})"),
              "probability: give either every (every Nth request) or probability");
    EXPECT_EQ(error(R"({"action":"drop","color":"red"})"),
              "color: unknown key; expected one of action, delay_ms, exception, garbage_bytes, "
              "functions, addresses, every, probability");
    EXPECT_EQ(error(R"({"action":"drop","enabled":"yes"})"), "enabled: expected true or false");
    EXPECT_EQ(h.json(h.call("GET", "/api/units/1/faults")).size(), 1U);
}

// A client looping on POST: the rules stop at a bound, with a reason, instead of growing the
// process (the HTTP fuzz target found it).
TEST(DeviceApi, AUnitTakesAtMost256FaultRules) {
    WebHarness h;
    const std::string rule = R"({"action":"drop","functions":[5]})";
    for (int i = 1; i < 256; ++i)
        ASSERT_EQ(h.call("POST", "/api/units/1/faults", rule).status, 201) << i;
    const auto refused = h.call("POST", "/api/units/1/faults", rule);
    EXPECT_EQ(refused.status, 409);
    EXPECT_EQ(h.json(refused).value("error", ""), "unit 1 has 256 fault rules, the most it takes");
    EXPECT_EQ(h.call("PUT", "/api/units/1/faults/255", rule).status, 200);
}

TEST(DeviceApi, CountersPerUnitAndFunctionAndTheirReset) {
    WebHarness h;
    h.ask("03 00 00 00 01");
    h.ask("03 00 00 00 01");
    h.ask("06 00 00 00 01");  // the profile's fault answers 06
    h.ask("03 00 00 00 01", 2);
    auto counters = h.json(h.call("GET", "/api/counters"));
    EXPECT_EQ(counters["requests"],
              nlohmann::json::parse(R"([{"unit":1,"function":3,"requests":2,"exceptions":0},
                                        {"unit":1,"function":6,"requests":1,"exceptions":1},
                                        {"unit":2,"function":3,"requests":1,"exceptions":0}])"));
    EXPECT_EQ(counters["latency"]["count"], 4);
    EXPECT_EQ(counters["connections"], 3);
    EXPECT_EQ(counters["units"][0]["bus_messages"], 4);  // unit 2's request is on its bus too
    EXPECT_EQ(counters["units"][0]["bus_exceptions"], 1);

    auto reset = h.call("POST", "/api/counters/reset");
    EXPECT_EQ(reset.status, 200);
    counters = h.json(reset);
    EXPECT_EQ(counters["requests"], nlohmann::json::array());
    EXPECT_EQ(counters["units"][0]["bus_messages"], 0);
    // FC 08 sub 0B (bus message count) agrees: this request is the first since the reset.
    EXPECT_EQ(h.ask("08 00 0B 00 00"), "08 00 0B 00 01");
}

TEST(DeviceApi, LiveEventCarriesCountersAndThePageShown) {
    WebHarness h;
    h.ask("06 00 01 00 2A");
    auto event = h.api().live_event(
        {{"unit", "1"}, {"bank", "holding_registers"}, {"start", "0"}, {"count", "2"}});
    EXPECT_EQ(event["page"]["values"], nlohmann::json::parse("[0,0]"));  // 06 refused: a fault
    EXPECT_EQ(event["counters"]["requests"][0]["exceptions"], 1);
    EXPECT_FALSE(h.api().live_event({}).contains("page"));
}

TEST(DeviceApi, ListsUnitsAndTheirRanges) {
    WebHarness h;
    auto units = h.json(h.call("GET", "/api/units"));
    ASSERT_EQ(units.size(), 2U);
    EXPECT_EQ(units[0]["unit"], 1);
    EXPECT_EQ(units[0]["banks"]["holding_registers"][1],
              nlohmann::json::parse(R"({"start":200,"count":10,"access":"rw","name":""})"));
}

TEST(DeviceApi, TrafficListsTheLoggedRequestsAfterTheOneAskedFor) {
    auto device = device_from(kWebProfile);
    web::RequestMeter meter;
    server::TrafficLog log(std::nullopt, server::TrafficFormat::Text, 3);
    server::LoggedHandler logged(*device, log, "line");
    web::ServeView view{*device, meter, [] { return std::uint64_t{0}; }, {}};
    view.traffic = &log;
    web::DeviceApi api(view);
    std::array<std::uint8_t, 260> response{};
    for (const char* pdu : {"03 00 00 00 01", "10 00 01 00 01 02 00 07", "03 01 2C 00 01"})
        logged.handle({1, device::Link::Tcp, "192.0.2.1:50312"}, hex(pdu), response);
    const auto reply = api.handle({"GET", "/api/traffic", {{"after", "1"}}, ""});
    EXPECT_EQ(reply.status, 200) << reply.body;
    const auto body = nlohmann::json::parse(reply.body);
    EXPECT_EQ(body["last"], 3);
    ASSERT_EQ(body["entries"].size(), 2U) << reply.body;
    EXPECT_EQ(body["entries"][0]["name"], "write multiple registers");
    EXPECT_EQ(body["entries"][0]["values"], nlohmann::json::array({7}));
    EXPECT_EQ(body["entries"][0]["peer"], "192.0.2.1:50312");
    EXPECT_EQ(body["entries"][1]["address"], 300);
    EXPECT_EQ(body["entries"][1]["exception"]["code"], 2);
    EXPECT_EQ(api.handle({"GET", "/api/traffic", {{"after", "x"}}, ""}).status, 400);
    // A server that keeps no log says so.
    WebHarness h;
    EXPECT_EQ(h.call("GET", "/api/traffic").status, 404);
}

TEST(DeviceApi, TypedPointsShowAsTheProfileLaysThemOutAndChooseTheFirstBank) {
    // The constant's registers are set when the behaviour first runs; the range's as declared.
    auto device = device_from(R"(
[[unit]]
id = 1
holding_registers = [{start = 0, count = 10}, {start = 20, count = 2, type = "u32", name = "energy", values = [65538]}]
input_registers = [{start = 0, count = 10, name = "temperature"}]
[[unit.behaviours]]
kind = "constant"
bank = "input_registers"
address = 2
type = "f32"
order = "CDAB"
value = 21.53
)");
    device->behaviours().advance(std::chrono::steady_clock::now(),
                                 std::chrono::system_clock::now());
    web::RequestMeter meter;
    web::DeviceApi api(web::ServeView{*device, meter, [] { return std::uint64_t{0}; }, {}});
    const auto units = nlohmann::json::parse(api.handle({"GET", "/api/units", {}, ""}).body);
    EXPECT_EQ(units[0]["start_bank"], "input_registers");
    auto page = api.live_event(
        {{"unit", "1"}, {"bank", "input_registers"}, {"start", "0"}, {"count", "10"}})["page"];
    ASSERT_EQ(page["points"].size(), 1U) << page.dump();
    EXPECT_EQ(page["points"][0]["address"], 2);
    EXPECT_EQ(page["points"][0]["name"], "temperature");
    EXPECT_EQ(page["points"][0]["type"], "f32");
    EXPECT_EQ(page["points"][0]["order"], "CDAB");
    EXPECT_NEAR(page["points"][0]["value"].get<double>(), 21.53, 1e-5);
    EXPECT_EQ(page["points"][0]["moving"], true);  // a behaviour's: the page draws its trend
    page = api.live_event(
        {{"unit", "1"}, {"bank", "holding_registers"}, {"start", "15"}, {"count", "10"}})["page"];
    ASSERT_EQ(page["points"].size(), 1U) << page.dump();
    EXPECT_EQ(page["points"][0]["name"], "energy");
    EXPECT_EQ(page["points"][0]["value"], 65538);
    EXPECT_EQ(page["points"][0]["moving"], false);
    // A page that cuts a point in two shows none of it.
    page = api.live_event(
        {{"unit", "1"}, {"bank", "holding_registers"}, {"start", "21"}, {"count", "5"}})["page"];
    EXPECT_FALSE(page.contains("points")) << page.dump();
}

}  // namespace
}  // namespace mblab::test
