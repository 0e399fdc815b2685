#include "conformance/answer_rules.hpp"

#include <fmt/core.h>

#include <variant>

#include "client/answer_check.hpp"
#include "protocol/request.hpp"
#include "protocol/response.hpp"

namespace mblab::conformance {

namespace {

constexpr std::uint8_t kBasic = 0x01;
constexpr std::uint8_t kRegular = 0x02;
constexpr std::uint8_t kIndividual = 0x04;
constexpr std::uint8_t kIndividualAccessBit = 0x80;
constexpr std::uint8_t kMoreFollows = 0xFF;

// The highest object id of a category: basic 00..02, regular 03..7F, extended 80..FF.
std::uint8_t last_object_of(std::uint8_t category) {
    switch (category) {
        case kBasic:
            return 0x02;
        case kRegular:
            return 0x7F;
        default:
            return 0xFF;
    }
}

std::string_view category_name(std::uint8_t category) {
    switch (category) {
        case kBasic:
            return "basic";
        case kRegular:
            return "regular";
        default:
            return "extended";
    }
}

// [APP] 6.1, 6.2: the bits past the quantity in the last byte are padded with zeros.
std::optional<std::string> pad_bits_broken(const protocol::ReadBitsRequest& request,
                                           const protocol::ReadBitsResponse& answer) {
    const unsigned used = request.quantity % 8U;
    if (used == 0 || answer.packed.empty()) return std::nullopt;
    const auto last = answer.packed.back();
    const auto unused = static_cast<std::uint8_t>(last & ~((1U << used) - 1U));
    if (unused == 0) return std::nullopt;
    return fmt::format(
        "unused bits of the last data byte: {:02X} holds bits set past the {} requested (mask "
        "{:02X}); they must be zero ([APP] 6.{})",
        last, request.quantity, unused,
        request.function == protocol::FunctionCode::ReadCoils ? 1 : 2);
}

// Device identification ([APP] 6.21), as decoded: the conformity level, the read code's
// category, object order, the first object, more follows and the next object id.
std::optional<std::string> device_id_rule_broken(std::uint8_t read_code, std::uint8_t object_id,
                                                 const protocol::ReadDeviceIdResponse& answer) {
    const auto level = static_cast<std::uint8_t>(answer.conformity_level & ~kIndividualAccessBit);
    const bool individual_allowed = (answer.conformity_level & kIndividualAccessBit) != 0;
    if (read_code == kIndividual && !individual_allowed) {
        return fmt::format(
            "conformity level {:02X} declares stream access only, yet individual access (read "
            "code 04) was answered with data: the level should be {:02X}",
            answer.conformity_level, answer.conformity_level | kIndividualAccessBit);
    }
    std::size_t offset = 0;
    protocol::DeviceIdObject object;
    int previous = -1;
    bool first = true;
    while (answer.next(offset, object)) {
        if (object.id > last_object_of(level)) {
            return fmt::format(
                "object {:02X} is beyond conformity level {:02X}, which declares {} "
                "identification (objects up to {:02X})",
                object.id, answer.conformity_level, category_name(level), last_object_of(level));
        }
        if (read_code != kIndividual && object.id > last_object_of(read_code)) {
            return fmt::format(
                "object {:02X} answers a {} stream request (read code {:02X}), which ends at "
                "object {:02X}",
                object.id, category_name(read_code), read_code, last_object_of(read_code));
        }
        if (static_cast<int>(object.id) <= previous) {
            return fmt::format("object ids out of order: {:02X} follows {:02X}", object.id,
                               previous);
        }
        // A stream starts at the object asked for or at a later one (a device may leave out
        // objects it does not have, or serve a category's own objects only), or over at 00 when
        // the object asked for does not exist; never before it.
        if (first && read_code != kIndividual && object.id < object_id && object.id != 0) {
            return fmt::format(
                "the first object is {:02X}; a stream from object {:02X} starts there or later, "
                "or at 00 when that object does not exist",
                object.id, object_id);
        }
        previous = object.id;
        first = false;
    }
    if (answer.more_follows == kMoreFollows) {
        if (previous < 0) return std::string("more follows is FF, yet the answer holds no object");
        if (answer.next_object_id <= previous) {
            return fmt::format(
                "next object id is {:02X} with more follows FF; it must name an object after "
                "the last one sent ({:02X})",
                answer.next_object_id, previous);
        }
    } else if (answer.next_object_id != 0) {
        return fmt::format("next object id is {:02X} with more follows 00; it must be 00",
                           answer.next_object_id);
    }
    return std::nullopt;
}

}  // namespace

std::optional<std::string> answer_rule_broken(std::span<const std::uint8_t> request_pdu,
                                              std::span<const std::uint8_t> answer_pdu) {
    auto request = protocol::decode_request(request_pdu);
    if (!request) return std::nullopt;
    if (std::holds_alternative<protocol::RawRequest>(*request)) return std::nullopt;
    auto answer = protocol::decode_response(answer_pdu);
    if (!answer) {
        const auto& error = answer.error();
        return fmt::format("{}: {}", error.field, error.reason);
    }
    if (std::holds_alternative<protocol::ExceptionResponse>(*answer)) return std::nullopt;
    if (auto mismatch = client::answer_mismatch(*request, *answer)) return mismatch;
    if (const auto* bits = std::get_if<protocol::ReadBitsRequest>(&*request)) {
        if (const auto* got = std::get_if<protocol::ReadBitsResponse>(&*answer)) {
            return pad_bits_broken(*bits, *got);
        }
    }
    if (const auto* id = std::get_if<protocol::ReadDeviceIdRequest>(&*request)) {
        if (const auto* got = std::get_if<protocol::ReadDeviceIdResponse>(&*answer)) {
            return device_id_rule_broken(id->read_code, id->object_id, *got);
        }
    }
    return std::nullopt;
}

}  // namespace mblab::conformance
