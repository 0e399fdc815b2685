#include "device/object_messaging.hpp"

#include "protocol/limits.hpp"

namespace mblab::device {

namespace {

constexpr std::uint16_t kServiceGetAttribute = 0x0007;

// Service error codes of mblab's reference device, 0001 to 0005 in the order docs/profiles.md
// lists them.
enum class ServiceError : std::uint16_t {
    ObjectNotFound = 1,
    ServiceNotSupported,
    AttributeNotFound,
    BadParameters,
    FragmentationNotSupported,
};

MaybeResponse reply(const protocol::ObjectMessagingRequest& request, std::uint16_t error,
                    std::span<const std::uint8_t> parameters) {
    protocol::ObjectMessagingResponse response;
    response.fragment_byte_count = static_cast<std::uint8_t>(
        protocol::limits::kMinObjectMessagingResponseFragment + parameters.size());
    response.fragment_protocol = 0;
    response.class_id = request.class_id;
    response.instance_id = request.instance_id;
    response.service_code = static_cast<std::uint16_t>(request.service_code + 1);
    response.error_code = error;
    response.parameters = parameters;
    return protocol::Response{response};
}

MaybeResponse service_error(const protocol::ObjectMessagingRequest& request, ServiceError error) {
    return reply(request, static_cast<std::uint16_t>(error), request.parameters);
}

}  // namespace

MaybeResponse serve_object_messaging(const protocol::ObjectMessagingRequest& request,
                                     const std::vector<SemiObject>& objects) {
    if (request.fragment_protocol != 0) {
        return service_error(request, ServiceError::FragmentationNotSupported);
    }
    const SemiObject* object = nullptr;
    for (const auto& candidate : objects) {
        if (candidate.class_id == request.class_id &&
            candidate.instance_id == request.instance_id) {
            object = &candidate;
        }
    }
    if (!object) return service_error(request, ServiceError::ObjectNotFound);
    if (request.service_code != kServiceGetAttribute) {
        return service_error(request, ServiceError::ServiceNotSupported);
    }
    if (request.parameters.size() != 2) return service_error(request, ServiceError::BadParameters);
    const auto id = static_cast<std::uint16_t>(request.parameters[0] << 8 | request.parameters[1]);
    for (const auto& attribute : object->attributes) {
        if (attribute.id == id) return reply(request, 0, attribute.value);
    }
    return service_error(request, ServiceError::AttributeNotFound);
}

}  // namespace mblab::device
