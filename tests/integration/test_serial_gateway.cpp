// The TCP-to-serial gateway: Modbus/TCP clients (our blocking client, mbpoll) reach the
// reference device on an RTU line over a socat pty pair through it. Units 1..10 are routed to
// the line; only unit 1 has a device there.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <chrono>
#include <memory>
#include <string>

#include "blocking_client.hpp"
#include "serial_test_support.hpp"
#include "server/background_server.hpp"
#include "server/gateway.hpp"

namespace mblab::test {
namespace {

using ::testing::HasSubstr;

class GatewayToRtu : public ::testing::Test {
  protected:
    // The gateway's response timeout for the line.
    virtual int timeout_ms() const { return 300; }
    void SetUp() override {
        ASSERT_EQ(line_.start("reference", "rtu", 19200, false), "");
        auto url = transport::parse_serial_url(
            "rtu://" + line_.pty().client_end() +
            "?baud=19200&units=1-10&timeout=" + std::to_string(timeout_ms()));
        ASSERT_TRUE(url) << url.error();
        auto gateway = server::make_gateway(*url);
        ASSERT_TRUE(gateway) << gateway.error();
        gateway_ = std::move(gateway.value());
        server_ = std::make_unique<server::BackgroundServer>(*gateway_);
        auto port = server_->start();
        ASSERT_TRUE(port) << port.error();
        port_ = *port;
    }
    void TearDown() override {
        if (server_) server_->stop();    // before the gateway it calls
        if (gateway_) gateway_->stop();  // its thread posts answers to the server's io_context
    }

    DeviceOnLine line_;
    std::unique_ptr<server::SerialGateway> gateway_;
    std::unique_ptr<server::BackgroundServer> server_;
    std::uint16_t port_ = 0;
};

TEST_F(GatewayToRtu, ReadsBackWhatItWroteThroughTheLine) {
    BlockingClient client(port_);
    ASSERT_TRUE(client.connected());
    EXPECT_EQ(client.transact("00 01 00 00 00 0B 01 10 00 64 00 02 04 12 34 56 78"),
              "00 01 00 00 00 06 01 10 00 64 00 02");
    EXPECT_EQ(client.transact("00 02 00 00 00 06 01 03 00 64 00 02"),
              "00 02 00 00 00 07 01 03 04 12 34 56 78");
    EXPECT_EQ(line_.device().data().value(1, device::BankKind::HoldingRegisters, 0x65), 0x5678);
    // FC 08 echo answers have no length field: the gateway ends them on t3.5 of silence.
    EXPECT_EQ(client.transact("00 03 00 00 00 06 01 08 00 00 AB CD"),
              "00 03 00 00 00 06 01 08 00 00 AB CD");
    // An exception from the device passes through as it is.
    EXPECT_EQ(client.transact("00 04 00 00 00 06 01 03 00 00 00 7E"), "00 04 00 00 00 03 01 83 03");
    EXPECT_EQ(gateway_->stats().answered.load(), 4u);
}

TEST_F(GatewayToRtu, AnswersTargetFailedForARoutedUnitWithoutADevice) {
    BlockingClient client(port_);
    ASSERT_TRUE(client.connected());
    EXPECT_EQ(client.transact("00 07 00 00 00 06 05 03 00 00 00 01"), "00 07 00 00 00 03 05 83 0B");
    EXPECT_EQ(gateway_->stats().timeouts.load(), 1u);
    // The line is still in step for the device that is there.
    EXPECT_EQ(client.transact("00 08 00 00 00 06 01 06 00 64 00 2A"),
              "00 08 00 00 00 06 01 06 00 64 00 2A");
}

TEST_F(GatewayToRtu, AnswersPathUnavailableForAnUnroutedUnit) {
    BlockingClient client(port_);
    ASSERT_TRUE(client.connected());
    EXPECT_EQ(client.transact("00 09 00 00 00 06 14 03 00 00 00 01"), "00 09 00 00 00 03 14 83 0A");
    EXPECT_EQ(client.transact("00 0A 00 00 00 06 FF 03 00 00 00 01"), "00 0A 00 00 00 03 FF 83 0A");
    EXPECT_EQ(gateway_->stats().forwarded.load(), 0u);
}

// The line waits for a silent device; the gateway's own answers, on another connection or
// behind it on the same one, do not wait with it (and keep their order on the connection).
class SlowGatewayToRtu : public GatewayToRtu {
  protected:
    int timeout_ms() const override { return 3000; }
};

TEST_F(SlowGatewayToRtu, ASilentDeviceStallsNoOtherConnection) {
    BlockingClient waiting(port_);
    BlockingClient other(port_);
    ASSERT_TRUE(waiting.connected() && other.connected());
    ASSERT_TRUE(waiting.send_hex("00 01 00 00 00 06 05 03 00 00 00 01"));  // unit 5: no device
    EXPECT_EQ(other.transact("00 02 00 00 00 06 14 03 00 00 00 01"), "00 02 00 00 00 03 14 83 0A");
    // Unit 5's answer is still owed: its 3 s response timeout has not run out.
    EXPECT_TRUE(waiting.read(1, std::chrono::milliseconds(20)).empty());
    EXPECT_EQ(waiting.read_adu(), "00 01 00 00 00 03 05 83 0B");
}

TEST_F(GatewayToRtu, AnswersKeepRequestOrderOnAConnection) {
    BlockingClient client(port_);
    ASSERT_TRUE(client.connected());
    // Unit 5 waits for the line's timeout, unit 20 is answered by the gateway at once, unit 1
    // by the device: the answers still come in request order.
    ASSERT_TRUE(
        client.send_hex("00 01 00 00 00 06 05 03 00 00 00 01"
                        "00 02 00 00 00 06 14 03 00 00 00 01"
                        "00 03 00 00 00 06 01 06 00 64 00 2A"));
    EXPECT_EQ(client.read_adu(), "00 01 00 00 00 03 05 83 0B");
    EXPECT_EQ(client.read_adu(), "00 02 00 00 00 03 14 83 0A");
    EXPECT_EQ(client.read_adu(), "00 03 00 00 00 06 01 06 00 64 00 2A");
}

// mbpoll counts references from 1: reference 201 is holding register 200.
TEST_F(GatewayToRtu, ServesMbpoll) {
    const auto port = std::to_string(port_);
    std::string output;
    ASSERT_EQ(run_command({"mbpoll", "-m", "tcp", "-p", port, "-a", "1", "-r", "201", "-1",
                           "127.0.0.1", "4660", "22136"},
                          output),
              0)
        << output;
    output.clear();
    ASSERT_EQ(run_command({"mbpoll", "-m", "tcp", "-p", port, "-a", "1", "-r", "201", "-c", "2",
                           "-1", "127.0.0.1"},
                          output),
              0)
        << output;
    EXPECT_THAT(output, HasSubstr("[201]: \t4660\n[202]: \t22136\n"));
    EXPECT_EQ(line_.device().data().value(1, device::BankKind::HoldingRegisters, 200), 4660);
    // Unit 5 is routed but silent: mbpoll reports the gateway's exception 0B.
    output.clear();
    EXPECT_NE(
        run_command({"mbpoll", "-m", "tcp", "-p", port, "-a", "5", "-r", "1", "-1", "127.0.0.1"},
                    output),
        0);
    EXPECT_THAT(output, HasSubstr("Target device failed to respond"));
}

}  // namespace
}  // namespace mblab::test
