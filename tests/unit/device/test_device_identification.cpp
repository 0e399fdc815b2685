// FC 2B / 0E stream access over several answers and the restart rule of [APP].
#include <gtest/gtest.h>

#include "device_harness.hpp"

namespace mblab::test {
namespace {

std::string long_text(char c) {
    return std::string(100, c);
}

// A unit with the basic objects "V", "P", "R" and `more` keys of its identification table.
std::unique_ptr<device::ReferenceDevice> identified(const std::string& more) {
    return device_from(
        "[[unit]]\nid = 1\n[unit.identification]\nvendor = \"V\"\n"
        "product_code = \"P\"\nrevision = \"R\"\n" +
        more);
}

std::unique_ptr<device::ReferenceDevice> long_objects() {
    return identified("product_name = \"" + long_text('a') + "\"\nmodel = \"" + long_text('b') +
                      "\"\nuser_application = \"" + long_text('c') + "\"\n");
}

TEST(DeviceIdentification, StreamSplitsWhenObjectsDoNotFit) {
    auto device = long_objects();
    // 0, 1, 2 (3 bytes each) and 4, 5 (102 each) fit in 246 bytes; 6 follows.
    const std::string first = ask(*device, "2B 0E 02 00");
    EXPECT_EQ(first.substr(0, 20), "2B 0E 02 82 FF 06 05");
    const std::string second = ask(*device, "2B 0E 02 06");
    EXPECT_EQ(second, "2B 0E 02 82 00 00 01 06 64 " + text_hex(long_text('c')));
}

TEST(DeviceIdentification, UnknownObjectInStreamRestartsAtZero) {
    auto device = shipped_device("reference");
    const std::string basic = ask(*device, "2B 0E 01 00");
    std::string restarted = ask(*device, "2B 0E 01 55");
    EXPECT_EQ(restarted, basic);
    // An object of a higher category than the code asks for restarts too.
    EXPECT_EQ(ask(*device, "2B 0E 01 80"), basic);
}

TEST(DeviceIdentification, ExtendedStreamIncludesPrivateObjects) {
    auto device = shipped_device("reference");
    EXPECT_EQ(ask(*device, "2B 0E 03 80"),
              "2B 0E 03 83 00 00 01 80 19 " + text_hex("mblab private object 0x80"));
}

TEST(DeviceIdentification, IndividualAccessToAMissingObjectIsIllegalDataAddress) {
    auto device = shipped_device("reference");
    EXPECT_EQ(ask(*device, "2B 0E 04 81"), "AB 02");
}

TEST(DeviceIdentification, BasicDeviceAnswersRegularRequestsWithWhatItHas) {
    auto device = identified("read_codes = [1, 2, 3]\n");
    EXPECT_EQ(ask(*device, "2B 0E 02 00"), "2B 0E 02 01 00 00 03 00 01 56 01 01 50 02 01 52");
    EXPECT_EQ(ask(*device, "2B 0E 04 00"), "AB 03");
}

TEST(ObjectMessaging, UnknownObjectAttributeAndServiceAreServiceErrors) {
    auto device = shipped_device("reference");
    EXPECT_EQ(ask(*device, "5B 09 00 00 02 00 01 00 07 00 01"),
              "5B 0B 00 00 02 00 01 00 08 00 01 00 01");
    EXPECT_EQ(ask(*device, "5B 09 00 00 01 00 01 00 07 00 09"),
              "5B 0B 00 00 01 00 01 00 08 00 03 00 09");
    EXPECT_EQ(ask(*device, "5B 09 00 00 01 00 01 00 01 00 01"),
              "5B 0B 00 00 01 00 01 00 02 00 02 00 01");
    EXPECT_EQ(ask(*device, "5B 09 00 00 01 00 01 00 07 00 02"),
              "5B 1F 00 00 01 00 01 00 08 00 00 " + text_hex("mblab reference device"));
}

TEST(ObjectMessaging, DeviceWithoutFunction5BAnswersIllegalFunction) {
    auto device = shipped_device("rs485-instrument");
    EXPECT_EQ(ask(*device, "5B 09 00 00 01 00 01 00 07 00 01"), "DB 01");
}

}  // namespace
}  // namespace mblab::test
