#pragma once

#include <cstdint>
#include <span>

#include "device/maybe_response.hpp"
#include "device/profile.hpp"
#include "protocol/request.hpp"

// FC 2B / MEI 0E, read device identification ([APP] 6.21): stream access by category
// (basic, regular, extended) split over several answers when the objects do not fit, and
// individual access to one object.
namespace mblab::device {

MaybeResponse serve_device_identification(const protocol::ReadDeviceIdRequest& request,
                                          const IdentitySpec& spec,
                                          std::span<std::uint8_t> scratch);

// 0x01 basic, 0x02 regular, 0x03 extended; +0x80 when individual access (code 04) is served.
std::uint8_t conformity_level(const IdentitySpec& spec);

}  // namespace mblab::device
