#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include "device/reference_device.hpp"

// Drives a ReferenceDevice the way a server does: request PDU hex in, response PDU hex out.
namespace mblab::test {

// Loads profiles/<name>.toml from the source tree; fails the test if it does not load.
std::unique_ptr<device::ReferenceDevice> shipped_device(std::string_view name);
// Loads profile text; fails the test if it does not load.
std::unique_ptr<device::ReferenceDevice> device_from(std::string_view toml);
// The loader's error for profile text ("" if it loaded).
std::string profile_error(std::string_view toml);

// The response PDU as hex, or "NO ANSWER" / "CLOSE".
std::string ask(device::ReferenceDevice& device, std::string_view request_hex,
                std::uint8_t unit = 1, device::Link link = device::Link::Tcp);
// As ask(), with the reply's delay.
device::Reply ask_reply(device::ReferenceDevice& device, std::string_view request_hex,
                        std::string& response_hex, std::uint8_t unit = 1,
                        device::Link link = device::Link::Tcp);

}  // namespace mblab::test

namespace mblab::test {
// "6D 62" for "mb": text as it appears on the wire.
std::string text_hex(std::string_view text);
}  // namespace mblab::test
