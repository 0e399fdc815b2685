#include "protocol/device_id.hpp"

#include "protocol/limits.hpp"
#include "protocol/message_checks.hpp"
#include "protocol/response.hpp"
#include "support/escaped_text.hpp"

namespace mblab::protocol {

namespace {

constexpr std::uint8_t kMoreFollows = 0xFF;
constexpr std::uint8_t kNoMoreFollows = 0x00;
constexpr std::uint8_t kIndividualAccessBit = 0x80;

bool read_object(std::span<const std::uint8_t> objects, std::size_t offset, DeviceIdObject& out) {
    if (offset > objects.size()) return false;
    ReadCursor in(objects.subspan(offset));
    std::uint8_t length = 0;
    return in.read_u8(out.id) && in.read_u8(length) && in.read_bytes(length, out.value);
}

}  // namespace

std::string DeviceIdObject::text() const {
    return escaped_text(value);
}

bool ReadDeviceIdResponse::next(std::size_t& offset, DeviceIdObject& out) const {
    if (!read_object(objects, offset, out)) return false;
    offset += 2 + out.value.size();
    return true;
}

bool encode_device_id_object(WriteCursor& out, std::uint8_t id,
                             std::span<const std::uint8_t> value) {
    if (value.size() > 0xFF) return false;
    out.put_u8(id);
    out.put_u8(static_cast<std::uint8_t>(value.size()));
    out.put_bytes(value);
    return out.ok();
}

namespace detail {

void check_read_device_id_response(FieldReader& reader, const ReadDeviceIdHeader& header,
                                   std::span<const std::uint8_t> objects) {
    check_read_device_id_code(reader, header.read_code);
    const auto level = static_cast<std::uint8_t>(header.conformity_level & ~kIndividualAccessBit);
    reader.require(level >= 0x01 && level <= 0x03,
                   value_error("conformity level", "must be 01..03 or 81..83"));
    reader.require(header.more_follows == kNoMoreFollows || header.more_follows == kMoreFollows,
                   value_error("more follows", "must be 00 or FF"));
    if (header.read_code == limits::kReadDeviceIdIndividual) {
        reader.require(header.more_follows == kNoMoreFollows,
                       value_error("more follows", "must be 00 for individual access (code 04)"));
        reader.require(header.object_count == 1,
                       value_error("number of objects", "must be 1 for individual access"));
    }
    ReadDeviceIdResponse walker;
    walker.objects = objects;
    std::size_t offset = 0;
    std::size_t count = 0;
    DeviceIdObject object;
    while (offset < objects.size() && walker.next(offset, object))
        ++count;
    reader.require(offset == objects.size(),
                   value_error("object length", "an object runs past the end of the PDU"));
    reader.require(count == header.object_count,
                   value_error("number of objects", "must equal the objects in the PDU"));
}

}  // namespace detail

}  // namespace mblab::protocol
