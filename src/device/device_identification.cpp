#include "device/device_identification.hpp"

#include <algorithm>

#include "protocol/limits.hpp"

namespace mblab::device {

namespace {

using protocol::ExceptionCode;

constexpr auto kFc = static_cast<std::uint8_t>(protocol::FunctionCode::EncapsulatedInterface);
// Function, MEI type, code, conformity, more follows, next object, object count.
constexpr std::size_t kHeader = 7;
constexpr std::size_t kObjectRoom = protocol::limits::kMaxPdu - kHeader;

constexpr std::uint8_t kIndividual = 0x04;

std::uint8_t last_id_of(std::uint8_t read_code) {
    switch (read_code) {
        case 0x01:
            return 0x02;
        case 0x02:
            return 0x7F;
        default:
            return 0xFF;
    }
}

const IdentityObject* find_object(const IdentitySpec& spec, std::uint8_t id) {
    for (const auto& object : spec.objects) {
        if (object.id == id) return &object;
    }
    return nullptr;
}

std::size_t put_object(const IdentityObject& object, std::span<std::uint8_t> out) {
    out[0] = object.id;
    out[1] = static_cast<std::uint8_t>(object.value.size());
    std::copy(object.value.begin(), object.value.end(), out.begin() + 2);
    return object.value.size() + 2;
}

}  // namespace

std::uint8_t conformity_level(const IdentitySpec& spec) {
    std::uint8_t level = 0x01;
    for (const auto& object : spec.objects) {
        if (object.id >= 0x80) {
            level = 0x03;
        } else if (object.id >= 0x03 && level < 0x02) {
            level = 0x02;
        }
    }
    return spec.read_codes[kIndividual] ? static_cast<std::uint8_t>(level | 0x80) : level;
}

MaybeResponse serve_device_identification(const protocol::ReadDeviceIdRequest& request,
                                          const IdentitySpec& spec,
                                          std::span<std::uint8_t> scratch) {
    if (request.read_code == 0 || request.read_code >= spec.read_codes.size() ||
        !spec.read_codes[request.read_code]) {
        return exception_response(kFc, ExceptionCode::IllegalDataValue);
    }
    protocol::ReadDeviceIdResponse response;
    response.read_code = request.read_code;
    response.conformity_level = conformity_level(spec);
    const IdentityObject* named = find_object(spec, request.object_id);

    if (request.read_code == kIndividual) {
        if (!named) return exception_response(kFc, ExceptionCode::IllegalDataAddress);
        response.object_count = 1;
        response.objects = scratch.first(put_object(*named, scratch));
        return protocol::Response{response};
    }

    const std::uint8_t last = last_id_of(request.read_code);
    std::uint8_t first = request.object_id;
    if (!named || first > last) {
        if (!spec.unknown_object_restarts) {
            return exception_response(kFc, ExceptionCode::IllegalDataAddress);
        }
        first = 0;
    }
    std::size_t used = 0;
    for (const auto& object : spec.objects) {
        if (object.id < first || object.id > last) continue;
        if (used + object.value.size() + 2 > kObjectRoom) {
            response.more_follows = 0xFF;
            response.next_object_id = object.id;
            break;
        }
        used += put_object(object, scratch.subspan(used));
        ++response.object_count;
    }
    response.objects = scratch.first(used);
    return protocol::Response{response};
}

}  // namespace mblab::device
