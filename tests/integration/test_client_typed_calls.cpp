#include <gtest/gtest.h>

#include "client/client.hpp"
#include "client/target.hpp"
#include "test_client_support.hpp"

// The typed calls of client::Client, one or more per public function code, against the
// reference device in-process.
namespace mblab::test {
namespace {

using namespace std::chrono_literals;

class ClientTypedCalls : public ClientCliTest {
  protected:
    void SetUp() override {
        start_reference_server();
        auto target = client::parse_target(tcp_target(port_));
        ASSERT_TRUE(target);
        target_ = *target;
        transactor_ = std::make_unique<client::Transactor>(
            target_.name, [this] { return client::open_link(target_, 1s); },
            client::TransactionOptions{1, 3000ms, 0});
        client_ = std::make_unique<client::Client>(*transactor_);
    }

    client::Target target_;
    std::unique_ptr<client::Transactor> transactor_;
    std::unique_ptr<client::Client> client_;
};

TEST_F(ClientTypedCalls, BitsAndRegisters) {
    auto& c = *client_;
    ASSERT_TRUE(c.write_multiple_coils(10, {true, false, true}));
    ASSERT_TRUE(c.write_single_coil(13, true));
    EXPECT_EQ(*c.read_coils(10, 4), (std::vector<bool>{true, false, true, true}));
    EXPECT_EQ(c.read_discrete_inputs(0, 3)->size(), 3U);
    const std::vector<std::uint16_t> values = {0x1111, 0x2222};
    ASSERT_TRUE(c.write_multiple_registers(500, values));
    ASSERT_TRUE(c.write_single_register(502, 0x3333));
    EXPECT_EQ(*c.read_holding_registers(500, 3),
              (std::vector<std::uint16_t>{0x1111, 0x2222, 0x3333}));
    EXPECT_EQ(c.read_input_registers(0, 5)->size(), 5U);
    ASSERT_TRUE(c.mask_write_register(502, 0x00FF, 0x0100));
    EXPECT_EQ(c.read_holding_registers(502, 1)->front(), 0x0133);
    const std::vector<std::uint16_t> written = {7, 8};
    EXPECT_EQ(*c.read_write_multiple_registers(500, 2, 500, written), written);
}

TEST_F(ClientTypedCalls, SerialLineFunctions) {
    auto& c = *client_;
    EXPECT_EQ(*c.read_exception_status(), 0);
    const std::vector<std::uint8_t> data = {0xCA, 0xFE};
    auto echo = c.diagnostics(0, data);
    ASSERT_TRUE(echo) << echo.error().message;
    EXPECT_EQ(echo->data, data);
    auto counter = c.get_comm_event_counter();
    ASSERT_TRUE(counter);
    EXPECT_EQ(counter->status, 0);
    auto log = c.get_comm_event_log();
    ASSERT_TRUE(log);
    EXPECT_FALSE(log->events.empty());
    auto id = c.report_server_id();
    ASSERT_TRUE(id);
    EXPECT_EQ(std::string(id->begin(), id->begin() + 5), "mblab");
    EXPECT_EQ(c.diagnostics(4, {}).error().kind, client::ErrorKind::Invalid);
}

TEST_F(ClientTypedCalls, ListenOnlyModeSilencesTheDeviceUntilRestart) {
    // A short timeout: the read below is meant to go unanswered.
    client::Transactor transactor(
        target_.name, [this] { return client::open_link(target_, 1s); },
        client::TransactionOptions{1, 300ms, 0});
    client::Client c(transactor);
    ASSERT_TRUE(c.send_listen_only());
    auto silent = c.read_holding_registers(0, 1);
    ASSERT_FALSE(silent);
    EXPECT_EQ(silent.error().kind, client::ErrorKind::Timeout);
    // Restart communications is executed but, in listen-only mode, not answered.
    static constexpr std::uint8_t kRestart[] = {0x08, 0x00, 0x01, 0x00, 0x00};
    ASSERT_TRUE(transactor.send_only(kRestart));
    EXPECT_TRUE(client_->read_holding_registers(0, 1));
}

TEST_F(ClientTypedCalls, FilesAndFifo) {
    auto& c = *client_;
    const std::vector<client::FileRecordWrite> writes = {{1, 10, {1, 2, 3}}, {2, 0, {9}}};
    ASSERT_TRUE(c.write_file_records(writes));
    const std::vector<protocol::FileRecordRef> refs = {{1, 10, 3}, {2, 0, 2}};
    auto records = c.read_file_records(refs);
    ASSERT_TRUE(records) << records.error().message;
    EXPECT_EQ(*records, (std::vector<std::vector<std::uint16_t>>{{1, 2, 3}, {9, 0x1234}}));
    const std::vector<std::uint16_t> queue = {2, 0xAAAA, 0xBBBB};
    ASSERT_TRUE(c.write_multiple_registers(0x04DE, queue));
    EXPECT_EQ(*c.read_fifo_queue(0x04DE), (std::vector<std::uint16_t>{0xAAAA, 0xBBBB}));
}

TEST_F(ClientTypedCalls, IdentificationAndObjectMessaging) {
    auto& c = *client_;
    auto extended = c.read_device_identification(3);
    ASSERT_TRUE(extended) << extended.error().message;
    EXPECT_EQ(extended->objects.size(), 8U);
    EXPECT_EQ(extended->objects.back().id, 0x80);
    auto one = c.read_device_identification(4, 0x02);
    ASSERT_TRUE(one);
    ASSERT_EQ(one->objects.size(), 1U);
    EXPECT_EQ(one->objects[0].value, "0.1.0");
    client::ObjectMessage get;
    get.class_id = 1;
    get.instance_id = 1;
    get.service_code = 7;
    get.parameters = {0x00, 0x01};
    auto answer = c.object_messaging(get);
    ASSERT_TRUE(answer) << answer.error().message;
    EXPECT_EQ(answer->service_code, 8);
    EXPECT_EQ(answer->error_code, 0);
    EXPECT_EQ(answer->parameters, (std::vector<std::uint8_t>{0x00, 0x2B}));
}

TEST_F(ClientTypedCalls, ArgumentsOverTheLimitsAreNotSent) {
    auto& c = *client_;
    const std::vector<std::uint16_t> too_many(124, 0);
    auto refused = c.write_multiple_registers(0, too_many);
    ASSERT_FALSE(refused);
    EXPECT_EQ(refused.error().kind, client::ErrorKind::Invalid);
    EXPECT_EQ(refused.error().message,
              "write multiple registers: quantity: must be 1..123 (0x0001..0x007B), got 124");
    const std::vector<std::uint16_t> too_many_to_write(122, 0);
    auto read_write = c.read_write_multiple_registers(0, 1, 0, too_many_to_write);
    ASSERT_FALSE(read_write);
    EXPECT_EQ(read_write.error().message,
              "read/write multiple registers: quantity to write: must be 1..121 (0x0001..0x0079), "
              "got 122");
    EXPECT_EQ(c.read_holding_registers(0, 0).error().kind, client::ErrorKind::Invalid);
    EXPECT_EQ(c.raw({}).error().kind, client::ErrorKind::Invalid);
    EXPECT_EQ(server_->stats().requests.load(), 0U);
}

}  // namespace
}  // namespace mblab::test
