#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "device/maybe_response.hpp"
#include "device/profile.hpp"
#include "protocol/request.hpp"

// The files of FC 14/15: one 16-bit register per record. A sub-request outside a file, or
// naming a file the unit lacks, is exception 02; writes are checked whole before any is made.
namespace mblab::device {

class FileStore {
  public:
    FileStore() = default;
    explicit FileStore(std::vector<FileSpec> files) : files_(std::move(files)) {}

    MaybeResponse read(const protocol::ReadFileRecordRequest& request,
                       std::span<std::uint8_t> scratch) const;
    MaybeResponse write(const protocol::WriteFileRecordRequest& request);

    const std::vector<FileSpec>& files() const { return files_; }
    std::vector<FileSpec>& files() { return files_; }

  private:
    // The file holding every record `ref` names, or files_.size().
    std::size_t index_of(const protocol::FileRecordRef& ref) const;

    std::vector<FileSpec> files_;
};

}  // namespace mblab::device
