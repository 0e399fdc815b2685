// Byte-exact vectors: every frame decodes, and encoding the decoded message gives the same bytes.
// Sources: the examples of [APP] (Modbus Application Protocol v1.1b3, section 6), the frames of
// [CTP] (conformance test policy 2.1, sections 7 and 9, PDU part only), [INSTR] (an instrument's
// self-diagnostics) and [APP] 7 (an exception example).
#include <gtest/gtest.h>

#include <string>

#include "pdu_test_support.hpp"

namespace mblab::protocol {
namespace {

using testing::ascii_hex;
using testing::repeat_hex;

// ---- requests ----

const testing::PduCase kRequests[] = {
    // [APP] section 6 examples.
    {"App01ReadCoils", "01 00 13 00 13"},
    {"App02ReadDiscreteInputs", "02 00 C4 00 16"},
    {"App03ReadHoldingRegisters", "03 00 6B 00 03"},
    {"App04ReadInputRegisters", "04 00 08 00 01"},
    {"App05WriteSingleCoil", "05 00 AC FF 00"},
    {"App06WriteSingleRegister", "06 00 01 00 03"},
    {"App07ReadExceptionStatus", "07"},
    {"App08ReturnQueryData", "08 00 00 A5 37"},
    {"App0BGetCommEventCounter", "0B"},
    {"App0CGetCommEventLog", "0C"},
    {"App0FWriteMultipleCoils", "0F 00 13 00 0A 02 CD 01"},
    {"App10WriteMultipleRegisters", "10 00 01 00 02 04 00 0A 01 02"},
    {"App11ReportServerId", "11"},
    {"App14ReadFileRecord", "14 0E 06 00 04 00 01 00 02 06 00 03 00 09 00 02"},
    {"App15WriteFileRecord", "15 0D 06 00 04 00 07 00 03 06 AF 04 BE 10 0D"},
    {"App16MaskWriteRegister", "16 00 04 00 F2 00 25"},
    {"App17ReadWriteMultipleRegisters", "17 00 03 00 06 00 0E 00 03 06 00 FF 00 FF 00 FF"},
    {"App18ReadFifoQueue", "18 04 DE"},
    {"App2BReadDeviceIdBasic", "2B 0E 01 00"},
    {"App2BReadDeviceIdSecondTransaction", "2B 0E 01 02"},
    // [APP] 6.8.1: every sub-function with the data field it lists.
    {"App08Sub01Restart", "08 00 01 00 00"},
    {"App08Sub01RestartClearLog", "08 00 01 FF 00"},
    {"App08Sub02DiagnosticRegister", "08 00 02 00 00"},
    {"App08Sub03AsciiDelimiter", "08 00 03 0D 00"},
    {"App08Sub04ListenOnly", "08 00 04 00 00"},
    {"App08Sub0AClearCounters", "08 00 0A 00 00"},
    {"App08Sub0BBusMessages", "08 00 0B 00 00"},
    {"App08Sub0CBusErrors", "08 00 0C 00 00"},
    {"App08Sub0DBusExceptions", "08 00 0D 00 00"},
    {"App08Sub0EServerMessages", "08 00 0E 00 00"},
    {"App08Sub0FNoResponse", "08 00 0F 00 00"},
    {"App08Sub10Nak", "08 00 10 00 00"},
    {"App08Sub11Busy", "08 00 11 00 00"},
    {"App08Sub12Overrun", "08 00 12 00 00"},
    {"App08Sub14ClearOverrun", "08 00 14 00 00"},
    // Seed 000, section 7 (protocol test) and appendix 9 (exception tests).
    {"Seed000_7_3ReadCoils", "01 00 00 00 01"},
    {"Seed000_7_4ReadInputDiscretes", "02 00 00 00 01"},
    {"Seed000_7_5ReadMultipleRegisters", "03 00 00 00 01"},
    {"Seed000_7_6ReadInputRegister", "04 00 00 00 01"},
    {"Seed000_7_7WriteCoil", "05 00 00 FF 00"},
    {"Seed000_7_8WriteSingleRegister", "06 00 10 12 34"},
    {"Seed000_7_9ReadExceptionStatus", "07"},
    {"Seed000_7_10Diagnostics", "08 00 00 12 34"},
    {"Seed000_7_11ForceMultipleCoils", "0F 00 00 00 01 01 01"},
    {"Seed000_7_12WriteMultipleRegisters", "10 00 10 00 01 02 12 34"},
    {"Seed000_7_13ObjectMessaging", "5B 09 00 00 01 00 01 00 07 00 01"},
    {"Seed000_7_13_2SemiSignatureScan", "03 00 00 00 7D"},
    {"Seed000_9_1_1IllegalFunction", "25 00 01 00 01"},
    {"Seed000_9_1_2OutOfRange", "03 80 01 00 01"},
    // Seed 001: an FC 08 echo of 100 data words, device identification codes 01 and 04.
    {"Seed001EchoHundredWords", "08 00 00" + repeat_hex("5A", 200)},
    {"Seed001EchoOneWord", "08 00 00 00 01"},
    {"Seed001DeviceIdBasic", "2B 0E 01 00"},
    {"Seed001DeviceIdOneObject", "2B 0E 04 02"},
    // Seed 003: read one coil at 1245.
    {"Seed003ReadCoil", "01 04 A1 00 01"},
    // Beyond the examples: opaque and unknown codes, echoes of odd length.
    {"EchoOddLength", "08 00 00 01 02 03"},
    {"EchoNothing", "08 00 00"},
    {"CanopenGeneralReference", "2B 0D 00 01 02 03"},
    {"CanopenEmpty", "2B 0D"},
    {"UserDefinedFunction", "41 01 02 03"},
    {"BareUnknownFunction", "09"},
    {"FunctionZero", "00"},
    {"HighBitFunction", "81 00"},
    {"ObjectMessagingNoParameters", "5B 07 00 00 01 00 01 00 07"},
};

class RequestVector : public ::testing::TestWithParam<testing::PduCase> {};

TEST_P(RequestVector, DecodesAndEncodesToTheSameBytes) {
    testing::expect_round_trip(GetParam().pdu, decode_request);
}

INSTANTIATE_TEST_SUITE_P(Pdu, RequestVector, ::testing::ValuesIn(kRequests), testing::case_name);

// ---- responses ----

const std::string kCompany = ascii_hex("Company identification");                 // 0x16 bytes
const std::string kProductCode = ascii_hex("Product code XX");                    // 0x0F bytes
const std::string kLongProductCode = ascii_hex("Product code XXXXXXXXXXXXXXXX");  // 0x1D
const std::string kRevision = ascii_hex("V2.11");                                 // 0x05

const testing::PduCase kResponses[] = {
    // [APP] section 6 examples.
    {"App01ReadCoils", "01 03 CD 6B 05"},
    {"App02ReadDiscreteInputs", "02 03 AC DB 35"},
    {"App03ReadHoldingRegisters", "03 06 02 2B 00 00 00 64"},
    {"App04ReadInputRegisters", "04 02 00 0A"},
    {"App05WriteSingleCoil", "05 00 AC FF 00"},
    {"App06WriteSingleRegister", "06 00 01 00 03"},
    {"App07ReadExceptionStatus", "07 6D"},
    {"App08ReturnQueryData", "08 00 00 A5 37"},
    {"App0BGetCommEventCounter", "0B FF FF 01 08"},
    {"App0CGetCommEventLog", "0C 08 00 00 01 08 01 21 20 00"},
    {"App0FWriteMultipleCoils", "0F 00 13 00 0A"},
    {"App10WriteMultipleRegisters", "10 00 01 00 02"},
    {"App11ReportServerId", "11 03 2A FF 01"},
    {"App14ReadFileRecord", "14 0C 05 06 0D FE 00 20 05 06 33 CD 00 40"},
    {"App15WriteFileRecord", "15 0D 06 00 04 00 07 00 03 06 AF 04 BE 10 0D"},
    {"App16MaskWriteRegister", "16 00 04 00 F2 00 25"},
    {"App17ReadWriteMultipleRegisters", "17 0C 00 FE 0A CD 00 01 00 03 00 0D 00 FF"},
    {"App18ReadFifoQueue", "18 00 06 00 02 01 B8 12 84"},
    // [APP] 6.21 examples. The spec's own lengths and counts disagree with its strings (0x0D for
    // the 15-byte "Product code XX", three objects announced where two follow); these vectors
    // use the lengths and counts that match the bytes.
    {"App2BBasicInOneResponse",
     "2B 0E 01 01 00 00 03 00 16" + kCompany + "01 0F" + kProductCode + "02 05" + kRevision},
    {"App2BFirstTransaction", "2B 0E 01 01 FF 02 02 00 16" + kCompany + "01 1D" + kLongProductCode},
    {"App2BSecondTransaction", "2B 0E 01 01 00 00 01 02 05" + kRevision},
    {"App2BIndividualAccess", "2B 0E 04 81 00 00 01 02 05" + kRevision},
    // Counter sub-functions answer a value, not an echo.
    {"App08Sub02DiagnosticRegister", "08 00 02 12 34"},
    {"App08Sub0BBusMessages", "08 00 0B 01 08"},
    {"App08Sub01RestartEcho", "08 00 01 FF 00"},
    // Exceptions: [CTP] 9.1, [INSTR], [APP] 7.
    {"Seed003IllegalAddress", "81 02"},
    {"Seed000_9_1_1IllegalFunction", "A5 01"},
    {"Seed000_9_1_2OutOfRange", "83 02"},
    {"Seed000_9_1_3ImproperLength", "83 03"},
    {"Seed001UnknownMeiType", "AB 01"},
    {"Seed001UnknownObject", "AB 02"},
    {"Seed001BadReadCode", "AB 03"},
    {"MemoryParityError", "94 08"},
    {"GatewayTargetFailed", "83 0B"},
    // Seed 000, section 7 pass criteria with the XX bytes filled in.
    {"Seed000_7_3ReadCoils", "01 01 01"},
    {"Seed000_7_4ReadInputDiscretes", "02 01 00"},
    {"Seed000_7_5ReadMultipleRegisters", "03 02 12 34"},
    {"Seed000_7_6ReadInputRegister", "04 02 00 00"},
    {"Seed000_7_7WriteCoil", "05 00 00 FF 00"},
    {"Seed000_7_8WriteSingleRegister", "06 00 10 12 34"},
    {"Seed000_7_9ReadExceptionStatus", "07 00"},
    {"Seed000_7_10Diagnostics", "08 00 00 12 34"},
    {"Seed000_7_11ForceMultipleCoils", "0F 00 00 00 01"},
    {"Seed000_7_12WriteMultipleRegisters", "10 00 10 00 01"},
    {"Seed000_7_13ServiceError", "5B 0B 00 00 01 00 01 00 08 00 16 00 01"},
    {"Seed000_7_13ServiceData", "5B 0B 00 00 01 00 01 00 08 00 00 00 2A"},
    {"Seed000_7_13_2SemiSignature", "03 06 53 45 4D 49 5F 72"},
    // Seed 001: the echo of 100 data words.
    {"Seed001EchoHundredWords", "08 00 00" + repeat_hex("5A", 200)},
    // Beyond the examples.
    {"EmptyFifo", "18 00 02 00 00"},
    {"EventLogWithoutEvents", "0C 06 00 00 00 00 00 00"},
    {"CanopenGeneralReference", "2B 0D 00 01 02"},
    {"UserDefinedFunction", "41 01 02"},
    {"ObjectMessagingNoParameters", "5B 09 00 00 01 00 01 00 08 00 00"},
};

class ResponseVector : public ::testing::TestWithParam<testing::PduCase> {};

TEST_P(ResponseVector, DecodesAndEncodesToTheSameBytes) {
    testing::expect_round_trip(GetParam().pdu, decode_response);
}

INSTANTIATE_TEST_SUITE_P(Pdu, ResponseVector, ::testing::ValuesIn(kResponses), testing::case_name);

}  // namespace
}  // namespace mblab::protocol
