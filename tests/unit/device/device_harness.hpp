#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include "device/reference_device.hpp"
#include "support/device_profiles.hpp"

// Drives a ReferenceDevice the way a server does: request PDU hex in, response PDU hex out.
namespace mblab::test {

// The response PDU as hex, or "NO ANSWER" / "CLOSE".
std::string ask(device::ReferenceDevice& device, std::string_view request_hex,
                std::uint8_t unit = 1, device::Link link = device::Link::Tcp);
// As ask(), with the reply's delay.
device::Reply ask_reply(device::ReferenceDevice& device, std::string_view request_hex,
                        std::string& response_hex, std::uint8_t unit = 1,
                        device::Link link = device::Link::Tcp);

// Asks each request of `script` in turn and checks the answer. One exchange a line,
// "request -> answer" as ask() writes them; '#' starts a comment, and blank lines are skipped.
void expect_dialogue(device::ReferenceDevice& device, std::string_view script);

// A fixture on one shipped profile, asked on unit 1 over Modbus/TCP.
class ShippedDeviceTest : public ::testing::Test {
  protected:
    explicit ShippedDeviceTest(std::string_view profile) : device(shipped_device(profile)) {}
    std::string ask(std::string_view request) { return test::ask(*device, request); }
    void expect_dialogue(std::string_view script) { test::expect_dialogue(*device, script); }

    std::unique_ptr<device::ReferenceDevice> device;
};

}  // namespace mblab::test

namespace mblab::test {
// "6D 62" for "mb": text as it appears on the wire.
std::string text_hex(std::string_view text);
}  // namespace mblab::test
