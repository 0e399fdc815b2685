// A client decodes answers from devices it does not trust (a count past the bytes present,
// CVE-2023-26793): every count must match the bytes present and every field stay in range.
// Accepted answers at each limit round-trip; refused ones name the wire field at fault.
#include <gtest/gtest.h>

#include <string>

#include "pdu_test_support.hpp"

namespace mblab::protocol {
namespace {

using testing::repeat_hex;

const testing::PduCase kAccepted[] = {
    {"ReadCoilsOneByte", "01 01 00"},
    {"ReadCoils250Bytes", "01 FA" + repeat_hex("FF", 250)},
    {"ReadRegistersOne", "03 02 00 01"},
    {"ReadRegisters125", "03 FA" + repeat_hex("00", 250)},
    {"ReadInput125", "04 FA" + repeat_hex("00", 250)},
    {"ReadWrite125", "17 FA" + repeat_hex("00", 250)},
    {"WriteCoilsQuantity1968", "0F 00 00 07 B0"},
    {"WriteRegistersQuantity123", "10 00 00 00 7B"},
    {"EventLog64Events", "0C 46 00 00 00 01 00 02" + repeat_hex("20", 64)},
    {"EventLogOneEvent", "0C 07 00 00 00 01 00 02 04"},
    {"Fifo31", "18 00 40 00 1F" + repeat_hex("12", 62)},
    {"FifoOne", "18 00 04 00 01 12 34"},
    {"ServerIdOneByte", "11 01 FF"},
    {"FileRecordOneRegister", "14 04 03 06 12 34"},
    {"DeviceIdNoObjects", "2B 0E 01 01 00 00 00"},
    {"DeviceIdExtendedMoreFollows", "2B 0E 03 83 FF 81 01 80 01 41"},
    {"DeviceIdEmptyObject", "2B 0E 02 02 00 00 01 03 00"},
    {"EchoCounterAnyValue", "08 00 0E FF FF"},
    {"UndefinedExceptionCodeIsStillAnException", "83 09"},
};

class AcceptedResponse : public ::testing::TestWithParam<testing::PduCase> {};

TEST_P(AcceptedResponse, DecodesAndRoundTrips) {
    testing::expect_round_trip(GetParam().pdu, decode_response);
}

INSTANTIATE_TEST_SUITE_P(Strict, AcceptedResponse, ::testing::ValuesIn(kAccepted),
                         testing::case_name);

const testing::PduCase kRefused[] = {
    // Byte counts against the bytes present.
    {"ReadCoilsCountZero", "01 00", "byte count"},
    {"ReadCoilsCountOverData", "01 03 CD 6B", "byte count"},
    {"ReadCoilsCountUnderData", "01 02 CD 6B 05", "byte count"},
    {"ReadCoils251Bytes", "01 FB" + repeat_hex("FF", 251), "byte count"},
    {"ReadRegistersCountOdd", "03 03 00 01 02", "byte count"},
    {"ReadRegistersCountZero", "03 00", "byte count"},
    {"ReadRegisters126", "03 FC" + repeat_hex("00", 251), "byte count"},
    {"ReadRegistersCountOverData", "03 06 02 2B 00 00", "byte count"},
    {"ReadWriteCountOverData", "17 0C 00 FE", "byte count"},
    {"EventLogCountUnder6", "0C 05 00 00 00 00 00", "byte count"},
    {"EventLog65Events", "0C 47 00 00 00 01 00 02" + repeat_hex("20", 65), "byte count"},
    {"EventLogCountOverData", "0C 08 00 00 01 08 01 21 20", "byte count"},
    {"ServerIdCountZero", "11 00", "byte count"},
    {"ServerIdCountOverData", "11 05 2A FF", "byte count"},
    {"FifoCount32", "18 00 42 00 20" + repeat_hex("12", 64), "FIFO count"},
    {"FifoByteCountOverData", "18 00 08 00 02 01 B8 12 84", "byte count"},
    {"FifoCountDisagreesWithByteCount", "18 00 06 00 03 01 B8 12 84", "byte count"},
    {"FifoTruncated", "18 00", "byte count"},
    // Echo fields out of range.
    {"WriteCoilValue1234", "05 00 AC 12 34", "output value"},
    {"WriteCoilsQuantity0", "0F 00 00 00 00", "quantity"},
    {"WriteCoilsQuantity1969", "0F 00 00 07 B1", "quantity"},
    {"WriteRegistersQuantity124", "10 00 00 00 7C", "quantity"},
    {"WriteRegistersPastFFFF", "10 FF FF 00 02", "starting address"},
    {"RestartEchoBadData", "08 00 01 00 01", "data"},
    {"DiagnosticUnknownSub", "08 00 05 00 00", "sub-function"},
    {"DiagnosticCounterThreeBytes", "08 00 0B 00 00 00", "data"},
    // File records.
    {"ReadFileLengthZero", "14 00", "response data length"},
    {"ReadFileCountOverData", "14 0C 05 06 0D FE 00 20", "response data length"},
    {"ReadFileSubLengthEven", "14 05 04 06 0D FE 00", "file response length"},
    {"ReadFileSubLengthOne", "14 04 01 06 12 34", "file response length"},
    {"ReadFileSubOverrun", "14 06 07 06 0D FE 00 20", "file response length"},
    {"ReadFileReferenceType5", "14 04 03 05 12 34", "reference type"},
    {"WriteFileEchoBadReference", "15 09 07 00 01 00 00 00 01 12 34", "reference type"},
    {"WriteFileEchoOverrun", "15 0B 06 00 01 00 00 00 03 12 34 56 78", "record length"},
    // Device identification.
    {"DeviceIdFewerObjectsThanCount", "2B 0E 01 01 00 00 03 00 01 41", "number of objects"},
    {"DeviceIdMoreObjectsThanCount", "2B 0E 01 01 00 00 01 00 01 41 01 01 42", "number of objects"},
    {"DeviceIdObjectOverrun", "2B 0E 01 01 00 00 01 00 05 41 42", "object length"},
    {"DeviceIdHalfObjectHeader", "2B 0E 01 01 00 00 01 00", "object length"},
    {"DeviceIdReadCode05", "2B 0E 05 01 00 00 00", "read device id code"},
    {"DeviceIdConformity04", "2B 0E 01 04 00 00 00", "conformity level"},
    {"DeviceIdConformity80", "2B 0E 01 80 00 00 00", "conformity level"},
    {"DeviceIdMoreFollows01", "2B 0E 01 01 01 00 00", "more follows"},
    {"DeviceIdIndividualMoreFollows", "2B 0E 04 81 FF 03 01 02 01 41", "more follows"},
    {"DeviceIdIndividualTwoObjects", "2B 0E 04 81 00 00 02 00 01 41 01 01 42", "number of objects"},
    {"DeviceIdTruncatedHeader", "2B 0E 01 01 00", "next object id"},
    {"ReservedMeiType", "2B 0F 00", "MEI type"},
    // Object messaging (CTP 7.13.1.5).
    {"ObjectMessagingCountOverData", "5B 0C 00 00 01 00 01 00 08 00 16 00 01",
     "fragment byte count"},
    {"ObjectMessagingNoErrorCode", "5B 07 00 00 01 00 01 00 08", "fragment byte count"},
    // Exceptions and framing-level sizes.
    {"ExceptionWithoutCode", "83", "exception code"},
    {"ExceptionTrailing", "83 02 00", "PDU length"},
    {"ReadExceptionStatusEmpty", "07", "output data"},
    {"WriteRegisterTrailing", "06 00 01 00 03 00", "PDU length"},
    {"EmptyPdu", "", "function code"},
    {"PduOf254Bytes", "41" + repeat_hex("00", 253), "PDU length"},
};

class RefusedResponse : public ::testing::TestWithParam<testing::PduCase> {};

TEST_P(RefusedResponse, NamesTheField) {
    testing::expect_refused(GetParam().pdu, GetParam().field, decode_response);
}

INSTANTIATE_TEST_SUITE_P(Strict, RefusedResponse, ::testing::ValuesIn(kRefused),
                         testing::case_name);

}  // namespace
}  // namespace mblab::protocol
