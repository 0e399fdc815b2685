// The Modbus/TCP Conformance Test Policy 2.1 [CTP], every request/response frame of 7.3-7.13
// and 9.1.1-9.1.4, sent over a real socket to the reference profile; answers compared byte for
// byte. XX in the policy is the unit id, which the tests run with 1 (the profile's unit) and 0 and
// 0xFF (a direct server answers both).
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "blocking_client.hpp"
#include "server_fixture.hpp"
#include "support/hex.hpp"

namespace mblab::test {
namespace {

class ConformanceTestPolicy : public ServerFixture, public ::testing::WithParamInterface<int> {
  protected:
    void SetUp() override {
        start_reference_server();
        client_ = connect();
        ASSERT_TRUE(client_.connected());
    }
    // The policy's frame with XX replaced by the unit id under test.
    static std::string frame(std::string text) {
        auto unit = to_hex(std::vector<std::uint8_t>{static_cast<std::uint8_t>(GetParam())});
        for (auto at = text.find("XX"); at != std::string::npos; at = text.find("XX")) {
            text.replace(at, 2, unit);
        }
        return to_hex(hex(text));
    }
    std::string transact(const std::string& request) { return client_.transact(frame(request)); }

    BlockingClient client_;
};

TEST_P(ConformanceTestPolicy, ReadCoils_7_3) {
    EXPECT_EQ(transact("00 00 00 00 00 06 XX 01 00 00 00 01"),
              frame("00 00 00 00 00 04 XX 01 01 00"));
}

TEST_P(ConformanceTestPolicy, ReadInputDiscretes_7_4) {
    EXPECT_EQ(transact("00 00 00 00 00 06 XX 02 00 00 00 01"),
              frame("00 00 00 00 00 04 XX 02 01 00"));
}

// Holding register 0 is the first word of the SEMI signature ("SE").
TEST_P(ConformanceTestPolicy, ReadMultipleRegisters_7_5_1) {
    EXPECT_EQ(transact("00 00 00 00 00 06 XX 03 00 00 00 01"),
              frame("00 00 00 00 00 05 XX 03 02 53 45"));
}

// 7.5.2: a sweep of every quantity from 0, then of the whole memory in blocks of the maximum,
// then of a shrinking block at the end; lengths and byte counts must fit the quantity.
TEST_P(ConformanceTestPolicy, MultipleRegisterSweep_7_5_2) {
    auto check = [&](std::uint32_t address, std::uint32_t quantity) {
        auto request = hex(frame("00 00 00 00 00 06 XX 03"));
        request.push_back(static_cast<std::uint8_t>(address >> 8));
        request.push_back(static_cast<std::uint8_t>(address));
        request.push_back(0);
        request.push_back(static_cast<std::uint8_t>(quantity));
        auto answer = hex(client_.transact(to_hex(request)));
        ASSERT_EQ(answer.size(), 9 + 2 * quantity)
            << "address " << address << " quantity " << quantity;
        EXPECT_EQ(answer[5], 3 + 2 * quantity);
        EXPECT_EQ(answer[7], 0x03);
        EXPECT_EQ(answer[8], 2 * quantity);
    };
    constexpr std::uint32_t kMax = 125;
    constexpr std::uint32_t kRegisters = 0x10000;
    for (std::uint32_t quantity = 1; quantity <= kMax; ++quantity)
        check(0, quantity);
    for (std::uint32_t address = 0; address + kMax <= kRegisters; address += kMax) {
        check(address, kMax);
    }
    for (std::uint32_t address = kRegisters - kMax; address < kRegisters; ++address) {
        check(address, kRegisters - address);
    }
}

TEST_P(ConformanceTestPolicy, ReadInputRegister_7_6) {
    EXPECT_EQ(transact("00 00 00 00 00 06 XX 04 00 00 00 01"),
              frame("00 00 00 00 00 05 XX 04 02 00 00"));
}

TEST_P(ConformanceTestPolicy, WriteCoil_7_7) {
    EXPECT_EQ(transact("00 00 00 00 00 06 XX 05 00 00 FF 00"),
              frame("00 00 00 00 00 06 XX 05 00 00 FF 00"));
    EXPECT_EQ(transact("00 00 00 00 00 06 XX 01 00 00 00 01"),
              frame("00 00 00 00 00 04 XX 01 01 01"));
}

TEST_P(ConformanceTestPolicy, WriteSingleRegister_7_8) {
    EXPECT_EQ(transact("00 00 00 00 00 06 XX 06 00 10 12 34"),
              frame("00 00 00 00 00 06 XX 06 00 10 12 34"));
    EXPECT_EQ(transact("00 00 00 00 00 06 XX 03 00 10 00 01"),
              frame("00 00 00 00 00 05 XX 03 02 12 34"));
}

TEST_P(ConformanceTestPolicy, ReadExceptionStatus_7_9) {
    EXPECT_EQ(transact("00 00 00 00 00 02 XX 07"), frame("00 00 00 00 00 03 XX 07 00"));
}

TEST_P(ConformanceTestPolicy, DiagnosticsReturnQueryData_7_10) {
    EXPECT_EQ(transact("00 00 00 00 00 06 XX 08 00 00 12 34"),
              frame("00 00 00 00 00 06 XX 08 00 00 12 34"));
}

TEST_P(ConformanceTestPolicy, ForceMultipleCoils_7_11) {
    EXPECT_EQ(transact("00 00 00 00 00 08 XX 0F 00 00 00 01 01 01"),
              frame("00 00 00 00 00 06 XX 0F 00 00 00 01"));
}

TEST_P(ConformanceTestPolicy, WriteMultipleRegisters_7_12) {
    EXPECT_EQ(transact("00 00 00 00 00 09 XX 10 00 10 00 01 02 12 34"),
              frame("00 00 00 00 00 06 XX 10 00 10 00 01"));
}

// Class 1, instance 1, get attribute 1 (device type): service data 00 2B.
TEST_P(ConformanceTestPolicy, ObjectMessaging_7_13_1) {
    EXPECT_EQ(transact("00 00 00 00 00 0C XX 5B 09 00 00 01 00 01 00 07 00 01"),
              frame("00 00 00 00 00 0E XX 5B 0B 00 00 01 00 01 00 08 00 00 00 2B"));
}

// "SE", "MI" and their zero-sum checksum 0x5F72 from holding register 0.
TEST_P(ConformanceTestPolicy, ObjectMessagingAlternateEncoding_7_13_2) {
    EXPECT_EQ(transact("00 00 00 00 00 06 XX 03 00 00 00 03"),
              frame("00 00 00 00 00 09 XX 03 06 53 45 4D 49 5F 72"));
}

TEST_P(ConformanceTestPolicy, IllegalFunctionCode_9_1_1) {
    EXPECT_EQ(transact("00 00 00 00 00 06 XX 25 00 01 00 01"), frame("00 00 00 00 00 03 XX A5 01"));
}

// The reference profile maps all 65536 holding registers, so 0x8001 is valid; as 9.1.2's note
// says, an offset past the highest valid one is used instead: 0xFFFF with two registers.
TEST_P(ConformanceTestPolicy, OutOfRange_9_1_2) {
    EXPECT_EQ(transact("00 00 00 00 00 06 XX 03 80 01 00 01"),
              frame("00 00 00 00 00 05 XX 03 02 00 00"));
    EXPECT_EQ(transact("00 00 00 00 00 06 XX 03 FF FF 00 02"), frame("00 00 00 00 00 03 XX 83 02"));
}

TEST_P(ConformanceTestPolicy, ImproperMessageLength_9_1_3) {
    EXPECT_EQ(transact("00 00 00 00 00 FF XX 03 00 00 00 01"), frame("00 00 00 00 00 03 XX 83 03"));
    // And the connection is still in step.
    EXPECT_EQ(transact("00 01 00 00 00 06 XX 03 00 00 00 01"),
              frame("00 01 00 00 00 05 XX 03 02 53 45"));
}

TEST_P(ConformanceTestPolicy, IllegalNumberOfRegisters_9_1_4) {
    EXPECT_EQ(transact("00 00 00 00 00 06 XX 03 00 00 FF FF"), frame("00 00 00 00 00 03 XX 83 03"));
}

INSTANTIATE_TEST_SUITE_P(Units, ConformanceTestPolicy, ::testing::Values(0x01, 0x00, 0xFF),
                         [](const auto& info) { return "Unit" + std::to_string(info.param); });

}  // namespace
}  // namespace mblab::test
