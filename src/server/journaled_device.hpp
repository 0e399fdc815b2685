#pragma once

#include <optional>
#include <span>
#include <string>

#include "device/reference_device.hpp"
#include "device/request_handler.hpp"
#include "server/journal.hpp"

// The reference device behind `mblab serve --durable`: a request that changes the writable data
// is recorded in the journal, and its answer waits until the record is on disk. A TCP session
// lets the answer wait without waiting itself (the answers behind it keep their order); a serial
// line, one request at a time, waits. A record the disk refused turns the answer into exception
// 04 (server device failure): the write was made but is not durable, and the client must not
// take it as done.
namespace mblab::server {

class JournaledDevice final : public device::RequestHandler {
  public:
    JournaledDevice(device::ReferenceDevice& device, Journal& journal)
        : device_(device), journal_(journal) {}

    device::Reply handle(const device::RequestContext& context,
                         std::span<const std::uint8_t> request,
                         std::span<std::uint8_t> response) override;
    std::optional<device::Reply> handle_or_defer(const device::RequestContext& context,
                                                 std::span<const std::uint8_t> request,
                                                 std::span<std::uint8_t> response,
                                                 device::Deferral& deferral) override;

  private:
    device::ReferenceDevice& device_;
    Journal& journal_;
};

// A journal record: "UNIT T|S HEX-PDU". And back: false when the line is not one.
std::string journal_record(const device::RequestContext& context,
                           std::span<const std::uint8_t> request);
bool parse_journal_record(const std::string& line, device::RequestContext& context,
                          std::vector<std::uint8_t>& request);

}  // namespace mblab::server
