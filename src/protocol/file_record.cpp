#include "protocol/file_record.hpp"

#include "protocol/limits.hpp"
#include "protocol/request.hpp"
#include "protocol/response.hpp"

namespace mblab::protocol {

namespace {

constexpr std::size_t kSubRequestSize = limits::kFileRecordSubRequestSize;
constexpr std::uint32_t kRecordsPerFile = limits::kMaxFileRecordNumber + 1U;

// Reads the 7-byte header at `offset`; false when it does not fit.
bool read_ref(std::span<const std::uint8_t> subs, std::size_t offset, std::uint8_t& type,
              FileRecordRef& ref) {
    if (offset > subs.size()) return false;
    ReadCursor in(subs.subspan(offset));
    return in.read_u8(type) && in.read_u16(ref.file) && in.read_u16(ref.record) &&
           in.read_u16(ref.length);
}

}  // namespace

FileRecordRef ReadFileRecordRequest::at(std::size_t i) const {
    std::uint8_t type = 0;
    FileRecordRef ref;
    if (i >= count() || !read_ref(sub_requests, i * kSubRequestSize, type, ref)) return {};
    return ref;
}

bool WriteFileRecordRequest::next(std::size_t& offset, FileRecordData& out) const {
    std::uint8_t type = 0;
    FileRecordRef ref;
    if (!read_ref(sub_requests, offset, type, ref)) return false;
    const std::size_t data_at = offset + kSubRequestSize;
    const std::size_t data_size = std::size_t{ref.length} * 2;
    if (sub_requests.size() - data_at < data_size) return false;
    out.ref = ref;
    out.data = RegisterView(sub_requests.subspan(data_at, data_size));
    offset = data_at + data_size;
    return true;
}

bool ReadFileRecordResponse::next(std::size_t& offset, RegisterView& out) const {
    // Each sub-response: file response length L, reference type, then L - 1 bytes of registers.
    if (offset >= sub_responses.size()) return false;
    const std::size_t length = sub_responses[offset];
    if (length < 1 || sub_responses.size() - offset - 1 < length) return false;
    out = RegisterView(sub_responses.subspan(offset + 2, length - 1));
    offset += 1 + length;
    return true;
}

void encode_file_record_ref(WriteCursor& out, const FileRecordRef& ref) {
    out.put_u8(limits::kFileRecordReferenceType);
    out.put_u16(ref.file);
    out.put_u16(ref.record);
    out.put_u16(ref.length);
}

void encode_file_record_data(WriteCursor& out, const FileRecordData& record) {
    FileRecordRef ref = record.ref;
    ref.length = static_cast<std::uint16_t>(record.data.size());
    encode_file_record_ref(out, ref);
    out.put_bytes(record.data.bytes());
}

void encode_file_record_sub_response(WriteCursor& out, RegisterView data) {
    out.put_u8(static_cast<std::uint8_t>(1 + data.bytes().size()));
    out.put_u8(limits::kFileRecordReferenceType);
    out.put_bytes(data.bytes());
}

namespace detail {

namespace {

// [APP] figures 24 and 25: the reference must name an existing place, else exception 02.
void check_ref(FieldReader& reader, std::uint8_t type, const FileRecordRef& ref) {
    reader.require(type == limits::kFileRecordReferenceType,
                   address_error("reference type", "must be 6"));
    reader.require(ref.file >= 1, address_error("file number", "must be 0x0001..0xFFFF"));
    reader.require(ref.record <= limits::kMaxFileRecordNumber,
                   address_error("record number", "must be 0..9999 (0x0000..0x270F)"));
    reader.require(std::uint32_t{ref.record} + ref.length <= kRecordsPerFile,
                   address_error("record length", "record number + length runs past record 9999"));
}

void check_record_length(FieldReader& reader, const FileRecordRef& ref) {
    reader.require(ref.length >= 1, value_error("record length", "must be 1 or more registers"));
}

constexpr CountRule kReadRequestCount{
    "byte count", limits::kMinFileRecordByteCount, limits::kMaxFileRecordByteCount,
    limits::kFileRecordSubRequestSize, "must be 0x07..0xF5, 7 bytes a sub-request"};
constexpr CountRule kWriteCount{"request data length", limits::kMinWriteFileRecordByteCount,
                                limits::kMaxWriteFileRecordByteCount, 1, "must be 0x09..0xFB"};
// The smallest sub-response holds one register.
constexpr CountRule kReadResponseCount{"response data length", 4, limits::kMaxFileRecordByteCount,
                                       1, "must be 4..0xF5"};

void check_read_file_sub_requests(FieldReader& reader, std::span<const std::uint8_t> subs) {
    const ReadFileRecordRequest request{subs};
    // Each sub-response takes its length byte, reference type and 2 bytes a register.
    std::size_t response_bytes = 0;
    for (std::size_t i = 0; i < request.count(); ++i) {
        const FileRecordRef ref = request.at(i);
        check_record_length(reader, ref);
        response_bytes += 2 + 2 * std::size_t{ref.length};
    }
    reader.require(response_bytes <= limits::kMaxFileRecordByteCount,
                   value_error("record length",
                               "the registers asked for do not fit one response "
                               "(response data length above 0xF5)"));
    for (std::size_t i = 0; i < request.count(); ++i) {
        check_ref(reader, subs[i * kSubRequestSize], request.at(i));
    }
}

void check_write_file_sub_requests(FieldReader& reader, std::span<const std::uint8_t> subs) {
    std::size_t offset = 0;
    while (reader.ok() && offset < subs.size()) {
        std::uint8_t type = 0;
        FileRecordRef ref;
        reader.require(read_ref(subs, offset, type, ref),
                       value_error("sub-request", "a sub-request header runs past the byte count"));
        check_record_length(reader, ref);
        const std::size_t left = reader.ok() ? subs.size() - offset - kSubRequestSize : 0;
        reader.require(std::size_t{ref.length} * 2 <= left,
                       value_error("record length", "the record data runs past the byte count"));
        offset += kSubRequestSize + std::size_t{ref.length} * 2;
    }
    const WriteFileRecordRequest request{subs};
    FileRecordData record;
    offset = 0;
    while (reader.ok()) {
        const std::size_t header_at = offset;
        if (!request.next(offset, record)) break;
        check_ref(reader, subs[header_at], record.ref);
    }
}

void check_read_file_sub_responses(FieldReader& reader, std::span<const std::uint8_t> subs) {
    std::size_t offset = 0;
    while (reader.ok() && offset < subs.size()) {
        const std::size_t length = subs[offset];
        reader.require(length >= 3 && length % 2 == 1,
                       value_error("file response length",
                                   "must be odd and 3 or more (reference type + registers)"));
        reader.require(subs.size() - offset - 1 >= length,
                       value_error("file response length", "runs past the response data length"));
        if (!reader.ok()) return;
        reader.require(subs[offset + 1] == limits::kFileRecordReferenceType,
                       value_error("reference type", "must be 6"));
        offset += 1 + length;
    }
}

}  // namespace

void read_file_record_request_body(FieldReader& reader, std::span<const std::uint8_t>& subs) {
    reader.counted_rest(kReadRequestCount, subs);
    if (reader.ok()) check_read_file_sub_requests(reader, subs);
}

void write_file_record_body(FieldReader& reader, std::span<const std::uint8_t>& subs) {
    reader.counted_rest(kWriteCount, subs);
    if (reader.ok()) check_write_file_sub_requests(reader, subs);
}

void read_file_record_response_body(FieldReader& reader, std::span<const std::uint8_t>& subs) {
    reader.counted_rest(kReadResponseCount, subs);
    if (reader.ok()) check_read_file_sub_responses(reader, subs);
}

}  // namespace detail

}  // namespace mblab::protocol
