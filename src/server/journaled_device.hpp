#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "device/reference_device.hpp"
#include "device/request_handler.hpp"
#include "server/state_keeper.hpp"

// The reference device behind `mblab serve --durable`: a request that changes the writable data
// is recorded in the journal, and its answer waits until the record is on disk. A TCP session
// lets the answer wait without waiting itself (the answers behind it keep their order); a serial
// line, one request at a time, waits. A record the disk refused turns the answer into exception
// 04 (server device failure): the write was made but is not durable, and the client must not
// take it as done. The change and its record are made under the keeper's order lock, so that the
// journal holds the writes in the order the device made them, whatever side (Modbus, REST) made
// them.
namespace mblab::server {

class JournaledDevice final : public device::ForwardingHandler {
  public:
    explicit JournaledDevice(StateKeeper& keeper)
        : ForwardingHandler(keeper.device()), device_(keeper.device()), keeper_(keeper) {}

    std::optional<device::Reply> handle_or_defer(const device::RequestContext& context,
                                                 std::span<const std::uint8_t> request,
                                                 std::span<std::uint8_t> response,
                                                 device::Deferral& deferral) override;

  private:
    device::ReferenceDevice& device_;
    StateKeeper& keeper_;
};

// A journal record of a Modbus request: "UNIT T|S HEX-PDU". And back: false when the line is not
// one.
std::string journal_record(const device::RequestContext& context,
                           std::span<const std::uint8_t> request);
bool parse_journal_record(std::string_view line, device::RequestContext& context,
                          std::vector<std::uint8_t>& request);
// A journal record of values set without a request (the REST API): "UNIT V C|H START HEX", the
// start and each value as 4 hex digits.
std::string values_record(std::uint8_t unit, device::BankKind kind, std::uint32_t start,
                          std::span<const std::uint16_t> values);
// Makes the write a record holds again on `device`; false when the line is not a record.
bool replay_record(device::ReferenceDevice& device, std::string_view line);

}  // namespace mblab::server
