#include "device/file_store.hpp"

#include "protocol/limits.hpp"

namespace mblab::device {

namespace {

using protocol::ExceptionCode;

constexpr auto kRead = static_cast<std::uint8_t>(protocol::FunctionCode::ReadFileRecord);
constexpr auto kWrite = static_cast<std::uint8_t>(protocol::FunctionCode::WriteFileRecord);
// Function code and response data length precede the sub-responses.
constexpr std::size_t kSubResponseRoom = protocol::limits::kMaxPdu - 2;

}  // namespace

std::size_t FileStore::index_of(const protocol::FileRecordRef& ref) const {
    for (std::size_t i = 0; i < files_.size(); ++i) {
        if (files_[i].number != ref.file) continue;
        if (std::size_t{ref.record} + ref.length > files_[i].records.size()) break;
        return i;
    }
    return files_.size();
}

MaybeResponse FileStore::read(const protocol::ReadFileRecordRequest& request,
                              std::span<std::uint8_t> scratch) const {
    std::size_t needed = 0;
    for (std::size_t i = 0; i < request.count(); ++i)
        needed += 2 + 2 * std::size_t{request.at(i).length};
    if (needed > kSubResponseRoom)
        return exception_response(kRead, ExceptionCode::IllegalDataValue);
    for (std::size_t i = 0; i < request.count(); ++i) {
        if (index_of(request.at(i)) == files_.size())
            return exception_response(kRead, ExceptionCode::IllegalDataAddress);
    }
    std::size_t used = 0;
    for (std::size_t i = 0; i < request.count(); ++i) {
        const auto ref = request.at(i);
        const FileSpec& file = files_[index_of(ref)];
        scratch[used++] = static_cast<std::uint8_t>(1 + 2 * ref.length);
        scratch[used++] = protocol::limits::kFileRecordReferenceType;
        for (std::uint16_t r = 0; r < ref.length; ++r) {
            const std::uint16_t value = file.records[std::size_t{ref.record} + r];
            scratch[used++] = static_cast<std::uint8_t>(value >> 8);
            scratch[used++] = static_cast<std::uint8_t>(value & 0xFF);
        }
    }
    return protocol::Response{protocol::ReadFileRecordResponse{scratch.first(used)}};
}

MaybeResponse FileStore::write(const protocol::WriteFileRecordRequest& request) {
    std::size_t offset = 0;
    protocol::FileRecordData sub;
    while (request.next(offset, sub)) {
        if (index_of(sub.ref) == files_.size())
            return exception_response(kWrite, ExceptionCode::IllegalDataAddress);
    }
    offset = 0;
    while (request.next(offset, sub)) {
        FileSpec& file = files_[index_of(sub.ref)];
        for (std::size_t r = 0; r < sub.data.size(); ++r)
            file.records[sub.ref.record + r] = sub.data[r];
    }
    return protocol::Response{protocol::WriteFileRecordResponse{request.sub_requests}};
}

}  // namespace mblab::device
