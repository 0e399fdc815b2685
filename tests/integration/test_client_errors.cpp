#include <nlohmann/json.hpp>

#include "device/request_handler.hpp"
#include "support/ports.hpp"
#include "test_client_support.hpp"

// Exit statuses and the one line on stderr: exceptions a device answers (1, every code by name),
// usage errors and unreachable targets (2).
namespace mblab::test {
namespace {

// Answers every FC 03 request with the exception whose code is the low byte of the address.
class ExceptionDevice : public device::RequestHandler {
  public:
    device::Reply handle(const device::RequestContext&, std::span<const std::uint8_t> request,
                         std::span<std::uint8_t> response) override {
        response[0] = static_cast<std::uint8_t>(request[0] | 0x80);
        response[1] = request.size() > 3 ? request[2] : 0x01;
        device::Reply reply;
        reply.size = 2;
        return reply;
    }
};

class ClientErrors : public ClientCliTest {};

TEST_F(ClientErrors, EveryExceptionCodeIsShownByNameAndMeaning) {
    ExceptionDevice device;
    start_server(device);
    const std::vector<std::pair<std::string, std::string>> expected = {
        {"0x0001",
         "exception 01 illegal function: the device does not support function 0x03 "
         "(read holding registers)"},
        {"0x0002", "exception 02 illegal data address: 0x0002 is not on this device"},
        {"0x0003",
         "exception 03 illegal data value: a value or length in the request is not "
         "allowed"},
        {"0x0004",
         "exception 04 server device failure: the device failed while executing the "
         "request"},
        {"0x0005", "exception 05 acknowledge: the device accepted a long-running request"},
        {"0x0006", "exception 06 server device busy: the device is busy; retry later"},
        {"0x0007",
         "exception 07 negative acknowledge: the device cannot perform the program "
         "function"},
        {"0x0008",
         "exception 08 memory parity error: the device found a parity error in its "
         "memory"},
        {"0x000A", "exception 0A gateway path unavailable: the gateway has no path to the unit"},
        {"0x000B",
         "exception 0B gateway target failed to respond: the unit behind the gateway "
         "did not answer"},
        {"0x0042",
         "exception 42 unknown exception: an exception code not defined by the Modbus "
         "specification"},
    };
    for (const auto& [address, line] : expected) {
        auto ran = mblab("read", {"holding", address});
        EXPECT_EQ(ran.status, 1) << address;
        EXPECT_EQ(ran.out, "") << address;
        EXPECT_EQ(ran.err, "mblab read: " + line + "\n");
    }
}

TEST_F(ClientErrors, ExceptionInJsonNamesTheCode) {
    ExceptionDevice device;
    start_server(device);
    auto ran = mblab("read", {"holding", "2", "--json"});
    EXPECT_EQ(ran.status, 1);
    auto document = nlohmann::json::parse(ran.out);
    EXPECT_EQ(document["ok"], false);
    EXPECT_EQ(document["error"]["kind"], "exception");
    EXPECT_EQ(document["error"]["exception"]["code"], 2);
    EXPECT_EQ(document["error"]["exception"]["name"], "illegal data address");
}

TEST_F(ClientErrors, ADeviceWithHolesAnswersIllegalDataAddressForTheRange) {
    auto loaded =
        device::load_profile(std::string(MBLAB_SOURCE_DIR) + "/profiles/access-ranges.toml");
    ASSERT_TRUE(loaded) << loaded.error();
    device_ = std::move(loaded.value());
    start_server(*device_);
    auto hole = mblab("read", {"holding", "0x04A1"});
    expect_failed(hole, 1,
                  "mblab read: exception 02 illegal data address: 0x04A1 is not on this "
                  "device\n");
    auto range = mblab("read", {"holding", "25", "10"});
    EXPECT_EQ(range.err,
              "mblab read: exception 02 illegal data address: 0x0019..0x0022 are not "
              "all on this device\n");
    auto read_only = mblab("write", {"register", "10", "1"});
    expect_failed(read_only, 1,
                  "mblab write: exception 02 illegal data address: 0x000A is not writable on this "
                  "device\n");
}

TEST(ClientUsage, AnUnreachableTargetIsExitStatusTwo) {
    const auto port = closed_port();
    auto ran = run_mblab({"read", tcp_target(port), "holding", "0"});
    EXPECT_EQ(ran.out, "");
    expect_failed(ran, 2,
                  "mblab read: cannot connect to " + tcp_target(port) + ": connection refused\n");
}

TEST(ClientUsage, BadArgumentsAreOneLineAndExitStatusTwo) {
    const std::string target = tcp_target(closed_port());
    const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
        {{"read", target, "holdings", "0"},
         "mblab read: unknown kind 'holdings' (one of: coils|discretes|holding|input ADDR "
         "[COUNT], exception-status, event-counter, event-log, server-id, fifo ADDR, file FILE "
         "RECORD [COUNT])\n"},
        {{"read", target, "holding", "70000"},
         "mblab read: ADDR must be a number from 0 to 65535 (decimal or 0x hex), got '70000'\n"},
        {{"read", target, "holding", "0", "100", "--type", "f32"},
         "mblab read: 100 f32 values take 200 registers; one read takes at most 125\n"},
        {{"read", target, "coils", "0", "--type", "f32"},
         "mblab read: --type applies to registers (holding, input, fifo, file), not coils\n"},
        {{"read", target, "fifo"}, "mblab read: 'fifo' takes 1 argument: fifo ADDR\n"},
        {{"write", target, "register", "0", "70000"},
         "mblab write: '70000' is not a u16 value (0..65535)\n"},
        {{"write", target, "register", "0", "1.5", "--type", "f32"},
         "mblab write: '1.5' takes 2 registers: use 'registers' to write more than one\n"},
        {{"write", target, "coil", "0", "2"},
         "mblab write: a coil value is 1, 0, on, off, true or false, got '2'\n"},
        {{"write", target, "mask", "0", "1"},
         "mblab write: wrong number of arguments: mask ADDR AND OR\n"},
        {{"diag", target, "nonsense"},
         "mblab diag: unknown sub-function 'nonsense' (a number, or a name: see mblab diag "
         "--help)\n"},
        {{"devid", target, "everything"},
         "mblab devid: 'everything' is not basic, regular, extended, an object id (0..255) or an "
         "object name\n"},
        {{"raw", target, "0G"},
         "mblab raw: '0G' is not hex: give the PDU as hex bytes, e.g. 03 00 00 00 0A\n"},
        {{"raw", target, "031"},
         "mblab raw: PDU token 1 '031' has an odd number of hex digits: give each byte as 1 or 2 "
         "digits, or whole bytes run together (03 00 00 00 0A or 030000000A)\n"},
        {{"read", "tcp://127.0.0.1:99999", "holding", "0"},
         "mblab read: bad address 'tcp://127.0.0.1:99999': port must be a number from 0 to "
         "65535 (expected tcp://HOST:PORT, e.g. tcp://127.0.0.1:502)\n"},
    };
    for (const auto& [args, line] : cases) {
        auto ran = run_mblab(args);
        EXPECT_EQ(ran.status, 2) << args[2];
        EXPECT_EQ(ran.out, "");
        EXPECT_EQ(ran.err, line);
    }
}

TEST_F(ClientErrors, RequestsOverTheLimitsOfTheSpecificationAreRefusedBeforeSending) {
    start_reference_server();
    auto ran = mblab("read", {"holding", "0xFFFF", "2"});
    expect_failed(ran, 2,
                  "mblab read: read holding registers: starting address: address + "
                  "quantity runs past 0xFFFF\n");
    auto coils = mblab("read", {"coils", "0", "2001"});
    EXPECT_EQ(coils.err, "mblab read: read coils: quantity: must be 1..2000 (0x0001..0x07D0)\n");
    EXPECT_EQ(server_->stats().requests.load(), 0U);
}

}  // namespace
}  // namespace mblab::test
