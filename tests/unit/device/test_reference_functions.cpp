// Every public function code on profiles/reference.toml, hex in / hex out.
#include <gtest/gtest.h>

#include "device_harness.hpp"

namespace mblab::test {
namespace {

class ReferenceDevice : public ShippedDeviceTest {
  protected:
    ReferenceDevice() : ShippedDeviceTest("reference") {}
};

TEST_F(ReferenceDevice, ReadsCoilsAndDiscreteInputs) {
    expect_dialogue(R"(
        01 00 00 00 01 -> 01 01 00
        02 00 00 00 01 -> 02 01 00
        01 FF F0 00 10 -> 01 02 00 00
    )");
}

TEST_F(ReferenceDevice, HoldingRegistersStartWithTheSemiSignature) {
    expect_dialogue(R"(
        03 00 00 00 03 -> 03 06 53 45 4D 49 5F 72
        06 00 01 00 00 -> 86 02  # the signature is read-only
    )");
}

TEST_F(ReferenceDevice, ReadsInputRegisters) {
    EXPECT_EQ(ask("04 00 00 00 01"), "04 02 00 00");
}

TEST_F(ReferenceDevice, ReadsTheWholeAddressSpace) {
    EXPECT_EQ(ask("03 FF FF 00 01"), "03 02 00 00");
    EXPECT_EQ(ask("04 FF 83 00 7D").substr(0, 5), "04 FA");
    EXPECT_EQ(ask("03 80 01 00 01"), "03 02 00 00");
}

TEST_F(ReferenceDevice, WritesSingleCoilAndReadsItBack) {
    expect_dialogue(R"(
        05 00 00 FF 00 -> 05 00 00 FF 00
        01 00 00 00 01 -> 01 01 01
        05 00 00 00 00 -> 05 00 00 00 00
        01 00 00 00 01 -> 01 01 00
    )");
}

TEST_F(ReferenceDevice, WritesSingleRegisterAndReadsItBack) {
    expect_dialogue(R"(
        06 00 10 12 34 -> 06 00 10 12 34
        03 00 10 00 01 -> 03 02 12 34
    )");
}

TEST_F(ReferenceDevice, ReadsExceptionStatus) {
    EXPECT_EQ(ask("07"), "07 00");
}

TEST_F(ReferenceDevice, EchoesDiagnosticQueryData) {
    EXPECT_EQ(ask("08 00 00 12 34"), "08 00 00 12 34");
}

TEST_F(ReferenceDevice, WritesMultipleCoils) {
    expect_dialogue(R"(
        0F 00 00 00 01 01 01    -> 0F 00 00 00 01
        0F 00 13 00 0A 02 CD 01 -> 0F 00 13 00 0A
        01 00 13 00 0A          -> 01 02 CD 01
    )");
}

TEST_F(ReferenceDevice, WritesMultipleRegisters) {
    expect_dialogue(R"(
        10 00 10 00 02 04 12 34 56 78 -> 10 00 10 00 02
        03 00 10 00 02                -> 03 04 12 34 56 78
    )");
}

TEST_F(ReferenceDevice, ReportsServerId) {
    EXPECT_EQ(ask("11"),
              "11 1C " + text_hex("mblab") + " FF " + text_hex("mblab reference device"));
}

TEST_F(ReferenceDevice, ReadsAndWritesFileRecords) {
    expect_dialogue(R"(
        14 07 06 00 02 00 00 00 02                      -> 14 06 05 06 12 34 12 34
        15 09 06 00 01 00 05 00 01 AB CD                -> 15 09 06 00 01 00 05 00 01 AB CD
        14 0E 06 00 01 00 05 00 01 06 00 02 00 63 00 01 -> 14 08 03 06 AB CD 03 06 12 34
    )");
}

TEST_F(ReferenceDevice, MaskWritesRegister) {
    expect_dialogue(R"(
        06 00 20 00 12       -> 06 00 20 00 12
        16 00 20 00 F2 00 25 -> 16 00 20 00 F2 00 25
        03 00 20 00 01       -> 03 02 00 17
    )");
}

TEST_F(ReferenceDevice, ReadWriteMultipleWritesFirst) {
    EXPECT_EQ(ask("17 00 11 00 02 00 11 00 01 02 AB CD"), "17 04 AB CD 00 00");
}

TEST_F(ReferenceDevice, ReadsFifoQueue) {
    expect_dialogue(R"(
        18 04 DE -> 18 00 08 00 03 01 B8 12 84 00 00
        18 00 10 -> 98 02
    )");
}

TEST_F(ReferenceDevice, ReadsBasicDeviceIdentification) {
    EXPECT_EQ(ask("2B 0E 01 00"), "2B 0E 01 83 00 00 03 00 05 " + text_hex("mblab") + " 01 09 " +
                                      text_hex("MBLAB-REF") + " 02 05 " + text_hex("0.1.0"));
}

TEST_F(ReferenceDevice, ReadsOnePrivateObject) {
    EXPECT_EQ(ask("2B 0E 04 80"),
              "2B 0E 04 83 00 00 01 80 19 " + text_hex("mblab private object 0x80"));
}

TEST_F(ReferenceDevice, AnswersSemiGetAttribute) {
    // CTP 7.13.1.4 / 7.13.1.5.3
    EXPECT_EQ(ask("5B 09 00 00 01 00 01 00 07 00 01"), "5B 0B 00 00 01 00 01 00 08 00 00 00 2B");
}

TEST_F(ReferenceDevice, AnswersEventCounterAndLog) {
    expect_dialogue(R"(
        0B -> 0B 00 00 00 00
        # Newest first: the receive of this 0C, the send and receive of the 0B.
        0C -> 0C 09 00 00 00 00 00 02 80 40 80
    )");
}

TEST_F(ReferenceDevice, DeclaresItsLimits) {
    const auto declared = device->declarations().first();
    EXPECT_EQ(declared.unit, 1);
    EXPECT_EQ(declared.max_read_registers, 125);
    EXPECT_EQ(declared.holding_registers, 65536u);
    EXPECT_EQ(declared.semi_signature, 0);
    EXPECT_TRUE(declared.object_messaging);
}

}  // namespace
}  // namespace mblab::test
