#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "device/maybe_response.hpp"
#include "device/profile.hpp"
#include "protocol/request.hpp"

// FC 5B SEMI object messaging (CTP 7.13): "get attribute" on the profile's objects. Every
// request the function can carry gets a service response: data, or a service error code with
// the request's parameters echoed, answered with service code + 1.
namespace mblab::device {

inline constexpr std::uint16_t kServiceGetAttribute = 0x0007;

// Service error codes of mblab's reference device (docs/profiles.md).
enum class ServiceError : std::uint16_t {
    ObjectNotFound = 0x0001,
    ServiceNotSupported = 0x0002,
    AttributeNotFound = 0x0003,
    BadParameters = 0x0004,
    FragmentationNotSupported = 0x0005,
};

MaybeResponse serve_object_messaging(const protocol::ObjectMessagingRequest& request,
                                     const std::vector<SemiObject>& objects);

}  // namespace mblab::device
