#pragma once

#include <cstdint>
#include <span>

#include "protocol/cursor.hpp"
#include "protocol/request.hpp"
#include "protocol/shared_fields.hpp"

// Encoding support shared by the request and response codecs (not part of the public API).
namespace mblab::protocol::detail {

// Big-endian 16-bit fields in order; returns true so writers can end with it.
template <class... Words>
bool put_words(WriteCursor& out, Words... words) {
    (out.put_u16(static_cast<std::uint16_t>(words)), ...);
    return true;
}

// A one-byte count, then the bytes it counts. False when they are too many for the count byte.
inline bool put_counted(WriteCursor& out, std::span<const std::uint8_t> bytes) {
    if (bytes.size() > 0xFF) return false;
    out.put_u8(static_cast<std::uint8_t>(bytes.size()));
    out.put_bytes(bytes);
    return true;
}

// FC 5B, both directions: the fields up to the service code, the words a direction adds after
// them (a response's error code), then the parameters. The fragment byte count is derived from
// what follows it, so an encoded message agrees with itself; `min_fragment` counts all but the
// parameters.
template <class... Words>
bool put_object_messaging(WriteCursor& out, const ObjectMessagingHeader& message,
                          std::size_t min_fragment, std::span<const std::uint8_t> parameters,
                          Words... words) {
    const std::size_t fragment = min_fragment + parameters.size();
    if (fragment > 0xFF) return false;
    out.put_u8(static_cast<std::uint8_t>(fragment));
    out.put_u8(message.fragment_protocol);
    put_words(out, message.class_id, message.instance_id, message.service_code, words...);
    out.put_bytes(parameters);
    return true;
}

// Writes the fields after the function code of the layouts both directions share; the request
// and response writers add their own messages. False when a length does not fit its count field.
struct SharedBodyWriter {
    WriteCursor& out;

    template <FunctionCode Code>
    bool operator()(const AddressValue<Code>& m) const {
        return put_words(out, m.address, m.value);
    }
    bool operator()(const DiagnosticsFields& m) const {
        put_words(out, m.sub_function);
        out.put_bytes(m.data);
        return true;
    }
    bool operator()(const WriteFileRecordFields& m) const {
        return put_counted(out, m.sub_requests);
    }
    bool operator()(const MaskWriteFields& m) const {
        return put_words(out, m.address, m.and_mask, m.or_mask);
    }
    bool operator()(const CanopenFields& m) const {
        out.put_u8(m.mei_type);
        out.put_bytes(m.data);
        return true;
    }
    bool operator()(const RawFields& m) const {
        out.put_bytes(m.data);
        return true;
    }
};

}  // namespace mblab::protocol::detail
