// DeviceState::save / load: the writable data survives a restart of the device.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "device_harness.hpp"

namespace mblab::test {
namespace {

using device::BankKind;

constexpr std::string_view kTiny = R"(
name = "tiny"
[[unit]]
id = 3
coils = [{start = 0, count = 3}]
holding_registers = [{start = 10, count = 2, values = [1, 2]}, {start = 12, access = "ro"}]
files = [{number = 4, records = 2}]
)";

TEST(DeviceState, SavesWritableRangesAndFiles) {
    auto device = device_from(kTiny);
    EXPECT_EQ(ask(*device, "05 00 01 FF 00", 3), "05 00 01 FF 00");
    EXPECT_EQ(ask(*device, "15 09 06 00 04 00 01 00 01 00 2A", 3),
              "15 09 06 00 04 00 01 00 01 00 2A");
    const auto expected = nlohmann::json::parse(R"({
        "format": "mblab-device-state", "version": 1, "profile": "tiny",
        "units": [{"id": 3,
                   "coils": [{"start": 0, "values": [0, 1, 0]}],
                   "holding_registers": [{"start": 10, "values": [1, 2]}],
                   "files": [{"number": 4, "records": [0, 42]}]}]})");
    EXPECT_EQ(nlohmann::json::parse(device->state().save()), expected);
}

TEST(DeviceState, RoundTripsThroughAFreshDevice) {
    auto before = shipped_device("reference");
    EXPECT_EQ(ask(*before, "06 00 10 12 34"), "06 00 10 12 34");
    EXPECT_EQ(ask(*before, "05 00 05 FF 00"), "05 00 05 FF 00");
    EXPECT_EQ(ask(*before, "15 09 06 00 01 00 05 00 01 AB CD"), "15 09 06 00 01 00 05 00 01 AB CD");
    const std::string state = before->state().save();

    auto after = shipped_device("reference");
    std::string error;
    ASSERT_TRUE(after->state().load(state, error)) << error;
    EXPECT_EQ(ask(*after, "03 00 10 00 01"), "03 02 12 34");
    EXPECT_EQ(ask(*after, "01 00 05 00 01"), "01 01 01");
    EXPECT_EQ(ask(*after, "14 07 06 00 01 00 05 00 01"), "14 04 03 06 AB CD");
    EXPECT_EQ(after->state().save(), state);
}

struct BadState {
    std::string_view text;
    std::string_view error;
};

class DeviceStateErrors : public ::testing::TestWithParam<BadState> {};

TEST_P(DeviceStateErrors, RefusesWithoutChangingAnything) {
    auto device = device_from(kTiny);
    std::string error;
    EXPECT_FALSE(device->state().load(GetParam().text, error));
    EXPECT_EQ(error, GetParam().error);
    EXPECT_EQ(device->data().value(3, BankKind::HoldingRegisters, 10), 1);
}

INSTANTIATE_TEST_SUITE_P(
    Cases, DeviceStateErrors,
    ::testing::Values(
        BadState{"{", "the state is not valid JSON"},
        BadState{R"({"format": "x", "version": 1})",
                 "format: expected \"mblab-device-state\" version 1 (a file written by mblab "
                 "serve --state)"},
        BadState{R"({"format": "mblab-device-state", "version": 1, "units": [{"id": 9}]})",
                 "units[0].id: the profile has no unit 9"},
        BadState{R"({"format": "mblab-device-state", "version": 1, "units": [{"id": 3,
                   "holding_registers": [{"start": 10, "values": [7, 8]},
                                         {"start": 12, "values": [1]}]}]})",
                 "units[0].holding_registers[1].start: no writable range of the profile starts "
                 "there"},
        BadState{R"({"format": "mblab-device-state", "version": 1, "units": [{"id": 3,
                   "holding_registers": [{"start": 10, "values": [7]}]}]})",
                 "units[0].holding_registers[0].values: expected an array of 2 values"},
        BadState{R"({"format": "mblab-device-state", "version": 1, "units": [{"id": 3,
                   "coils": [{"start": 0, "values": [0, 2, 0]}]}]})",
                 "units[0].coils[0].values: values must be integers from 0 to 1"},
        BadState{R"({"format": "mblab-device-state", "version": 1, "units": [{"id": 3,
                   "files": [{"number": 5, "records": [0, 0]}]}]})",
                 "units[0].files[0].number: the profile has no such file"}));

}  // namespace
}  // namespace mblab::test
