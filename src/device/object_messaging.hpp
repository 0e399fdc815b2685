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

MaybeResponse serve_object_messaging(const protocol::ObjectMessagingRequest& request,
                                     const std::vector<SemiObject>& objects);

}  // namespace mblab::device
