#include <gtest/gtest.h>

#include "protocol/rtu_frame_length.hpp"
#include "support/hex.hpp"

namespace mblab::protocol {
namespace {

using test::hex;
using Kind = RtuFrameLength::Kind;

RtuFrameLength request(std::string_view head) {
    return rtu_frame_length(Direction::Request, hex(head));
}
RtuFrameLength response(std::string_view head) {
    return rtu_frame_length(Direction::Response, hex(head));
}

TEST(RtuFrameLength, NeedsTheFunctionCodeFirst) {
    EXPECT_EQ(request(""), (RtuFrameLength{Kind::NeedBytes, 2}));
    EXPECT_EQ(response("01"), (RtuFrameLength{Kind::NeedBytes, 2}));
}

TEST(RtuFrameLength, FixedRequests) {
    EXPECT_EQ(request("01 03"), (RtuFrameLength{Kind::Known, 8}));
    EXPECT_EQ(request("01 07"), (RtuFrameLength{Kind::Known, 4}));
    EXPECT_EQ(request("01 16"), (RtuFrameLength{Kind::Known, 10}));
    EXPECT_EQ(request("01 18"), (RtuFrameLength{Kind::Known, 6}));
}

TEST(RtuFrameLength, ByteCountAtAnOffset) {
    EXPECT_EQ(request("01 10 00 01 00 02"), (RtuFrameLength{Kind::NeedBytes, 7}));
    EXPECT_EQ(request("01 10 00 01 00 02 04"), (RtuFrameLength{Kind::Known, 13}));
    EXPECT_EQ(request("01 17 00 03 00 06 00 0E 00 03 06"), (RtuFrameLength{Kind::Known, 19}));
    EXPECT_EQ(response("01 03 FA"), (RtuFrameLength{Kind::Known, 255}));
    EXPECT_EQ(response("01 18 00"), (RtuFrameLength{Kind::NeedBytes, 4}));
    EXPECT_EQ(response("01 18 00 06"), (RtuFrameLength{Kind::Known, 12}));
}

TEST(RtuFrameLength, ExceptionResponsesAreFiveBytes) {
    EXPECT_EQ(response("01 83"), (RtuFrameLength{Kind::Known, 5}));
    EXPECT_EQ(response("01 C1"), (RtuFrameLength{Kind::Known, 5}));
    EXPECT_EQ(request("01 83").kind, Kind::Unknown);
}

TEST(RtuFrameLength, Diagnostics) {
    EXPECT_EQ(request("01 08 00"), (RtuFrameLength{Kind::NeedBytes, 4}));
    EXPECT_EQ(request("01 08 00 00").kind, Kind::Unknown);
    EXPECT_EQ(response("01 08 00 00").kind, Kind::Unknown);
    EXPECT_EQ(request("01 08 00 0B"), (RtuFrameLength{Kind::Known, 8}));
    EXPECT_EQ(request("01 08 00 63").kind, Kind::Unknown);
}

TEST(RtuFrameLength, DeviceIdentification) {
    EXPECT_EQ(request("01 2B"), (RtuFrameLength{Kind::NeedBytes, 3}));
    EXPECT_EQ(request("01 2B 0E"), (RtuFrameLength{Kind::Known, 7}));
    EXPECT_EQ(request("01 2B 0D").kind, Kind::Unknown);
    EXPECT_EQ(response("01 2B 0E 01 01 00 00"), (RtuFrameLength{Kind::NeedBytes, 8}));
    EXPECT_EQ(response("01 2B 0E 01 01 00 00 00"), (RtuFrameLength{Kind::Known, 10}));
    EXPECT_EQ(response("01 2B 0E 01 01 00 00 02"), (RtuFrameLength{Kind::NeedBytes, 10}));
    EXPECT_EQ(response("01 2B 0E 01 01 00 00 02 00 03"), (RtuFrameLength{Kind::NeedBytes, 15}));
    EXPECT_EQ(response("01 2B 0E 01 01 00 00 02 00 03 41 42 43 01 00"),
              (RtuFrameLength{Kind::Known, 17}));
    EXPECT_EQ(response("01 2B 0D").kind, Kind::Unknown);
}

TEST(RtuFrameLength, DeviceIdentificationWalkStopsPastTheLimit) {
    auto head = hex("01 2B 0E 01 01 00 00 05 00 FF");
    head.resize(265, 0x00);  // object 0 of 255 bytes, then object 1 of length 0 ...
    const RtuFrameLength length = rtu_frame_length(Direction::Response, head);
    EXPECT_EQ(length.kind, Kind::Known);
    EXPECT_GT(length.bytes, 256U);
}

TEST(RtuFrameLength, UnknownFunctionCodes) {
    EXPECT_EQ(request("01 41").kind, Kind::Unknown);
    EXPECT_EQ(response("01 64").kind, Kind::Unknown);
}

}  // namespace
}  // namespace mblab::protocol
