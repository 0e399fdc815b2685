// Every limit of [APP] 6 at 0 / 1 / max / max + 1, and every bad input the PDU codec can see
// (counts, byte counts, lengths and values out of range): accepted requests round-trip, refused
// ones name the exception a server answers and the wire field at fault.
#include <gtest/gtest.h>

#include <string>

#include "pdu_test_support.hpp"

namespace mblab::protocol {
namespace {

using test::hex;
using testing::repeat_hex;

// ---- accepted at the limit ----

const testing::PduCase kAccepted[] = {
    {"ReadCoilsQuantity1", "01 00 00 00 01"},
    {"ReadCoilsQuantity2000", "01 00 00 07 D0"},
    {"ReadDiscreteInputsQuantity2000", "02 00 00 07 D0"},
    {"ReadHoldingQuantity125", "03 00 00 00 7D"},
    {"ReadInputQuantity125", "04 00 00 00 7D"},
    {"ReadRangeEndsAtFFFF", "03 FF 83 00 7D"},
    {"ReadLastCoil", "01 FF FF 00 01"},
    {"WriteCoilOff", "05 00 00 00 00"},
    {"WriteCoilsQuantity1", "0F 00 00 00 01 01 01"},
    {"WriteCoilsQuantity1968", "0F 00 00 07 B0 F6" + repeat_hex("FF", 246)},
    {"WriteCoilsEndAtFFFF", "0F FF FE 00 02 01 03"},
    {"WriteRegistersQuantity1", "10 00 00 00 01 02 00 00"},
    {"WriteRegistersQuantity123", "10 00 00 00 7B F6" + repeat_hex("00", 246)},
    {"ReadWriteRead1Write1", "17 00 00 00 01 00 00 00 01 02 12 34"},
    {"ReadWriteRead125", "17 00 00 00 7D 00 00 00 01 02 12 34"},
    {"ReadWriteWrite121", "17 00 00 00 01 00 00 00 79 F2" + repeat_hex("00", 242)},
    {"ReadFileByteCount07", "14 07 06 00 01 00 00 00 01"},
    {"ReadFileByteCountF5", "14 F5" + repeat_hex("06 00 01 00 00 00 01", 35)},
    {"ReadFileRecord9999", "14 07 06 00 01 27 0F 00 01"},
    {"ReadFileFileFFFF", "14 07 06 FF FF 00 00 00 01"},
    {"ReadFileLength121", "14 07 06 00 01 00 00 00 79"},
    {"WriteFileByteCount09", "15 09 06 00 01 00 00 00 01 12 34"},
    {"WriteFileByteCountFB", "15 FB 06 00 01 00 00 00 7A" + repeat_hex("AB", 244)},
    {"WriteFileTwoSubRequests",
     "15 14 06 00 01 00 00 00 01 12 34 06 00 02 27 0E 00 02 56 78 9A BC"},
    {"EchoLongest", "08 00 00" + repeat_hex("00", 250)},
    {"DeviceIdCode01", "2B 0E 01 00"},
    {"DeviceIdCode04", "2B 0E 04 FF"},
    {"ObjectMessagingFragment7", "5B 07 00 00 01 00 01 00 07"},
    {"LongestPdu", "41" + repeat_hex("00", 252)},
};

class AcceptedRequest : public ::testing::TestWithParam<testing::PduCase> {};

TEST_P(AcceptedRequest, DecodesAndRoundTrips) {
    testing::expect_round_trip(GetParam().pdu, decode_request);
}

INSTANTIATE_TEST_SUITE_P(Limit, AcceptedRequest, ::testing::ValuesIn(kAccepted),
                         testing::case_name);

// ---- refused ----

constexpr auto k01 = ExceptionCode::IllegalFunction;
constexpr auto k02 = ExceptionCode::IllegalDataAddress;
constexpr auto k03 = ExceptionCode::IllegalDataValue;

const testing::PduCase kRefused[] = {
    // 5. Quantity 0 or over the limit -> 03.
    {"ReadCoilsQuantity0", "01 00 00 00 00", "quantity", k03},
    {"ReadCoilsQuantity2001", "01 00 00 07 D1", "quantity", k03},
    {"ReadDiscreteInputsQuantity0", "02 00 00 00 00", "quantity", k03},
    {"ReadDiscreteInputsQuantity2001", "02 00 00 07 D1", "quantity", k03},
    {"ReadHoldingQuantity0", "03 00 00 00 00", "quantity", k03},
    {"ReadHoldingQuantity126", "03 00 00 00 7E", "quantity", k03},
    {"Seed000_9_1_4ReadHoldingQuantityFFFF", "03 00 00 FF FF", "quantity", k03},
    {"ReadInputQuantity0", "04 00 00 00 00", "quantity", k03},
    {"ReadInputQuantity126", "04 00 00 00 7E", "quantity", k03},
    {"WriteCoilsQuantity0", "0F 00 00 00 00 00", "quantity", k03},
    {"WriteCoilsQuantity1969", "0F 00 00 07 B1 F7" + repeat_hex("FF", 247), "quantity", k03},
    {"WriteRegistersQuantity0", "10 00 00 00 00 00", "quantity", k03},
    {"WriteRegistersQuantity124", "10 00 00 00 7C F8", "quantity", k03},
    {"ReadWriteRead0", "17 00 00 00 00 00 00 00 01 02 12 34", "quantity to read", k03},
    {"ReadWriteRead126", "17 00 00 00 7E 00 00 00 01 02 12 34", "quantity to read", k03},
    {"ReadWriteWrite0", "17 00 00 00 01 00 00 00 00 00", "quantity to write", k03},
    {"ReadWriteWrite122", "17 00 00 00 01 00 00 00 7A F4", "quantity to write", k03},
    // FC 05 value.
    {"WriteCoilValue0001", "05 00 00 00 01", "output value", k03},
    {"WriteCoilValue00FF", "05 00 00 00 FF", "output value", k03},
    {"WriteCoilValueFFFF", "05 00 00 FF FF", "output value", k03},
    // 6. Byte count that disagrees with the quantity or with the bytes present -> 03.
    {"WriteCoilsByteCountTooSmall", "0F 00 13 00 0A 01 CD", "byte count", k03},
    {"WriteCoilsByteCountTooLarge", "0F 00 13 00 0A 03 CD 01 00", "byte count", k03},
    {"WriteCoilsDataShort", "0F 00 13 00 0A 02 CD", "byte count", k03},
    {"WriteCoilsDataLong", "0F 00 13 00 0A 02 CD 01 00", "byte count", k03},
    {"WriteRegistersByteCountOdd", "10 00 01 00 02 03 00 0A 01", "byte count", k03},
    {"WriteRegistersByteCountTooLarge", "10 00 01 00 01 04 00 0A 01 02", "byte count", k03},
    {"WriteRegistersDataShort", "10 00 01 00 02 04 00 0A 01", "byte count", k03},
    {"ReadWriteByteCountNotTwiceWrite", "17 00 03 00 06 00 0E 00 03 04 00 FF 00 FF",
     "write byte count", k03},
    {"ReadWriteDataShort", "17 00 03 00 06 00 0E 00 03 06 00 FF 00 FF", "write byte count", k03},
    // 7. Address + quantity past 0xFFFF -> 02, both ranges of FC 17 (CVE-2022-0367).
    {"ReadCoilsPastFFFF", "01 FF FF 00 02", "starting address", k02},
    {"ReadHoldingPastFFFF", "03 FF 84 00 7D", "starting address", k02},
    {"ReadInputPastFFFF", "04 FF FF 00 02", "starting address", k02},
    {"WriteCoilsPastFFFF", "0F FF FF 00 02 01 03", "starting address", k02},
    {"WriteRegistersPastFFFF", "10 FF FF 00 02 04 00 01 00 02", "starting address", k02},
    {"ReadWriteReadPastFFFF", "17 FF FF 00 02 00 00 00 01 02 12 34", "read starting address", k02},
    {"ReadWriteWritePastFFFF", "17 00 00 00 01 FF FF 00 02 04 12 34 56 78",
     "write starting address", k02},
    // [APP] check order: quantity (03) before address (02).
    {"QuantityBeforeAddress", "03 FF FF 00 7E", "quantity", k03},
    {"WriteQuantityBeforeReadAddress", "17 FF FF 00 02 00 00 00 00 00", "quantity to write", k03},
    // 8. Function not supported: reserved MEI types and FC 08 sub-functions -> 01.
    {"Seed001MeiType0F", "2B 0F 01 00", "MEI type", k01},
    {"MeiType00", "2B 00", "MEI type", k01},
    {"MeiTypeFF", "2B FF 01 02", "MEI type", k01},
    {"DiagnosticSub05", "08 00 05 00 00", "sub-function", k01},
    {"DiagnosticSub13", "08 00 13 00 00", "sub-function", k01},
    {"DiagnosticSub15", "08 00 15 00 00", "sub-function", k01},
    {"DiagnosticSubFFFF", "08 FF FF 00 00", "sub-function", k01},
    // FC 08 data of the known sub-functions ([APP] 6.8.1) -> 03.
    {"RestartData0001", "08 00 01 00 01", "data", k03},
    {"AsciiDelimiterLowByte", "08 00 03 0D 01", "data", k03},
    {"ClearCountersData1234", "08 00 0A 12 34", "data", k03},
    {"CounterDataOneByte", "08 00 0B 00", "data", k03},
    {"CounterDataThreeBytes", "08 00 0B 00 00 00", "data", k03},
    {"ListenOnlyNoData", "08 00 04", "data", k03},
    // FC 2B / 0E read device id code.
    {"DeviceIdCode00", "2B 0E 00 00", "read device id code", k03},
    {"DeviceIdCode05", "2B 0E 05 00", "read device id code", k03},
    {"Seed001DeviceIdCodeFF", "2B 0E FF 00", "read device id code", k03},
    // 9. File records: byte count, overrunning sub-requests -> 03; references -> 02.
    {"ReadFileByteCount06", "14 06 06 00 01 00 00 00", "byte count", k03},
    {"ReadFileByteCountF6", "14 F6", "byte count", k03},
    {"ReadFileByteCountNotSevens", "14 08 06 00 01 00 00 00 01 00", "byte count", k03},
    {"ReadFileByteCountOverrunsPdu", "14 0E 06 00 01 00 00 00 01", "byte count", k03},
    {"ReadFileLength0", "14 07 06 00 01 00 00 00 00", "record length", k03},
    {"ReadFileAnswerTooLong", "14 07 06 00 01 00 00 00 7A", "record length", k03},
    {"ReadFileReferenceType5", "14 07 05 00 01 00 00 00 01", "reference type", k02},
    {"ReadFileFile0", "14 07 06 00 00 00 00 00 01", "file number", k02},
    {"ReadFileRecord10000", "14 07 06 00 01 27 10 00 01", "record number", k02},
    {"ReadFileRecordsPast9999", "14 07 06 00 01 27 0F 00 02", "record length", k02},
    {"ReadFileLengthBeforeReference", "14 0E 07 00 01 00 00 00 01 06 00 01 00 00 00 00",
     "record length", k03},
    {"WriteFileByteCount08", "15 08 06 00 01 00 00 00 01 12", "request data length", k03},
    {"WriteFileByteCountFC", "15 FC", "request data length", k03},
    {"WriteFileByteCountOverrunsPdu", "15 0B 06 00 01 00 00 00 01 12 34", "request data length",
     k03},
    {"WriteFileDataOverrunsByteCount", "15 0B 06 00 01 00 00 00 03 12 34 56 78", "record length",
     k03},
    {"WriteFileLengthFFFF", "15 09 06 00 01 00 00 FF FF 12 34", "record length", k03},
    {"WriteFileLength0", "15 09 06 00 01 00 00 00 00 12 34", "record length", k03},
    {"WriteFileHeaderOverrunsByteCount", "15 0E 06 00 01 00 00 00 01 12 34 06 00 01 00 00",
     "sub-request", k03},
    {"WriteFileReferenceType7", "15 09 07 00 01 00 00 00 01 12 34", "reference type", k02},
    {"WriteFileFile0", "15 09 06 00 00 00 00 00 01 12 34", "file number", k02},
    {"WriteFileRecord10000", "15 09 06 00 01 27 10 00 01 12 34", "record number", k02},
    {"WriteFileSecondReferenceBad",
     "15 14 06 00 01 00 00 00 01 12 34 06 00 02 27 0F 00 02 56 78 9A BC", "record length", k02},
    // FC 5B fragment byte count (CTP 7.13).
    {"ObjectMessagingCountTooLarge", "5B 0A 00 00 01 00 01 00 07 00 01", "fragment byte count",
     k03},
    {"ObjectMessagingCountTooSmall", "5B 08 00 00 01 00 01 00 07 00 01", "fragment byte count",
     k03},
    {"ObjectMessagingFragment6", "5B 06 00 00 01 00 01 00", "fragment byte count", k03},
    // 4. Truncated PDUs: a bare function code, or a field cut short -> 03.
    {"BareReadCoils", "01", "starting address", k03},
    {"BareReadDiscreteInputs", "02", "starting address", k03},
    {"BareReadHolding", "03", "starting address", k03},
    {"BareReadInput", "04", "starting address", k03},
    {"BareWriteCoil", "05", "output address", k03},
    {"BareWriteRegister", "06", "register address", k03},
    {"BareDiagnostics", "08", "sub-function", k03},
    {"BareWriteCoils", "0F", "starting address", k03},
    {"BareWriteRegisters", "10", "starting address", k03},
    {"BareReadFile", "14", "byte count", k03},
    {"BareWriteFile", "15", "request data length", k03},
    {"BareMaskWrite", "16", "reference address", k03},
    {"BareReadWrite", "17", "read starting address", k03},
    {"BareFifo", "18", "FIFO pointer address", k03},
    {"BareEncapsulated", "2B", "MEI type", k03},
    {"BareObjectMessaging", "5B", "fragment byte count", k03},
    {"ReadHoldingHalfQuantity", "03 00 6B 00", "quantity", k03},
    {"WriteCoilsNoByteCount", "0F 00 13 00 0A", "byte count", k03},
    {"MaskWriteNoOrMask", "16 00 04 00 F2", "or mask", k03},
    {"DeviceIdNoObjectId", "2B 0E 01", "object id", k03},
    {"DiagnosticsHalfSubFunction", "08 00", "sub-function", k03},
    // Bytes after the last field -> 03.
    {"ReadCoilsTrailing", "01 00 00 00 01 00", "PDU length", k03},
    {"ReadHoldingTrailing", "03 00 6B 00 03 00", "PDU length", k03},
    {"WriteCoilTrailing", "05 00 AC FF 00 00", "PDU length", k03},
    {"WriteRegisterTrailing", "06 00 01 00 03 00", "PDU length", k03},
    {"ExceptionStatusTrailing", "07 00", "PDU length", k03},
    {"EventCounterTrailing", "0B 00", "PDU length", k03},
    {"EventLogTrailing", "0C 00", "PDU length", k03},
    {"ServerIdTrailing", "11 00", "PDU length", k03},
    {"MaskWriteTrailing", "16 00 04 00 F2 00 25 00", "PDU length", k03},
    {"FifoTrailing", "18 04 DE 00", "PDU length", k03},
    {"DeviceIdTrailing", "2B 0E 01 00 00", "PDU length", k03},
    // Framing-level sizes.
    {"EmptyPdu", "", "function code", k03},
    {"PduOf254Bytes", "41" + repeat_hex("00", 253), "PDU length", k03},
};

class RefusedRequest : public ::testing::TestWithParam<testing::PduCase> {};

TEST_P(RefusedRequest, NamesTheExceptionAndField) {
    const DecodeError error =
        testing::expect_refused(GetParam().pdu, GetParam().field, decode_request);
    EXPECT_EQ(error.exception, GetParam().exception);
}

INSTANTIATE_TEST_SUITE_P(Limit, RefusedRequest, ::testing::ValuesIn(kRefused), testing::case_name);

TEST(RefusedRequest, ReasonsStateTheAllowedRange) {
    EXPECT_STREQ(decode_request(hex("03 00 00 00 7E")).error().reason,
                 "must be 1..125 (0x0001..0x007D)");
    EXPECT_STREQ(decode_request(hex("01 00 00 07 D1")).error().reason,
                 "must be 1..2000 (0x0001..0x07D0)");
    EXPECT_STREQ(decode_request(hex("0F 00 00 00 00 00")).error().reason,
                 "must be 1..1968 (0x0001..0x07B0)");
    EXPECT_STREQ(decode_request(hex("10 00 00 00 7C F8")).error().reason,
                 "must be 1..123 (0x0001..0x007B)");
    EXPECT_STREQ(decode_request(hex("17 00 00 00 01 00 00 00 7A F4")).error().reason,
                 "must be 1..121 (0x0001..0x0079)");
    EXPECT_STREQ(decode_request(hex("14 F6")).error().reason,
                 "must be 0x07..0xF5, 7 bytes a sub-request");
    EXPECT_STREQ(decode_request(hex("05 00 00 00 01")).error().reason,
                 "must be 0x0000 (off) or 0xFF00 (on)");
}

}  // namespace
}  // namespace mblab::protocol
