#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "client/client_error.hpp"
#include "client/transactor.hpp"
#include "protocol/request.hpp"
#include "protocol/response.hpp"
#include "protocol/result.hpp"

// Typed, blocking calls for every public function code. Each checks its arguments against
// [APP]'s limits before sending (ErrorKind::Invalid), decodes the answer strictly, checks that it
// answers the request (count, echo, sub-function), and turns an exception answer into
// ErrorKind::Exception with a message that names the code and what it means for this request.
namespace mblab::client {

template <class T>
using CallResult = protocol::Result<T, ClientError>;

struct DiagnosticsAnswer {
    std::uint16_t sub_function = 0;
    std::vector<std::uint8_t> data;
};

// FC 0B's answer holds no view into a buffer, so the client hands it on as decoded.
using EventCounter = protocol::GetCommEventCounterResponse;

struct EventLog {  // FC 0C
    std::uint16_t status = 0;
    std::uint16_t event_count = 0;
    std::uint16_t message_count = 0;
    std::vector<std::uint8_t> events;  // newest first
};

struct FileRecordWrite {  // one FC 15 sub-request
    std::uint16_t file = 0;
    std::uint16_t record = 0;
    std::vector<std::uint16_t> values;
};

struct IdentificationObject {
    std::uint8_t id = 0;
    std::string value;
};

struct DeviceIdentification {  // FC 2B / 0E, every answer of a stream read put together
    std::uint8_t read_code = 1;
    std::uint8_t conformity_level = 0;
    std::vector<IdentificationObject> objects;
    unsigned transactions = 0;
};

struct ObjectMessage {  // FC 5B request fields after the fragment byte count
    std::uint8_t fragment_protocol = 0;
    std::uint16_t class_id = 0;
    std::uint16_t instance_id = 0;
    std::uint16_t service_code = 0;
    std::vector<std::uint8_t> parameters;
};

struct ObjectMessageAnswer : ObjectMessage {
    std::uint16_t error_code = 0;  // 00 00: `parameters` hold the service data
};

class Client {
  public:
    explicit Client(Transactor& transactor) : transactor_(transactor) {}

    CallResult<std::vector<bool>> read_coils(std::uint16_t address, std::uint16_t count);
    CallResult<std::vector<bool>> read_discrete_inputs(std::uint16_t address, std::uint16_t count);
    CallResult<std::vector<std::uint16_t>> read_holding_registers(std::uint16_t address,
                                                                  std::uint16_t count);
    CallResult<std::vector<std::uint16_t>> read_input_registers(std::uint16_t address,
                                                                std::uint16_t count);
    CallResult<Done> write_single_coil(std::uint16_t address, bool on);
    CallResult<Done> write_single_register(std::uint16_t address, std::uint16_t value);
    CallResult<std::uint8_t> read_exception_status();
    // Sub-function 04 (force listen-only) is never answered: send it with send_listen_only().
    CallResult<DiagnosticsAnswer> diagnostics(std::uint16_t sub_function,
                                              std::span<const std::uint8_t> data);
    CallResult<Done> send_listen_only();
    CallResult<EventCounter> get_comm_event_counter();
    CallResult<EventLog> get_comm_event_log();
    CallResult<Done> write_multiple_coils(std::uint16_t address, const std::vector<bool>& values);
    CallResult<Done> write_multiple_registers(std::uint16_t address,
                                              std::span<const std::uint16_t> values);
    // The device-specific bytes: server id, run indicator, additional data.
    CallResult<std::vector<std::uint8_t>> report_server_id();
    // One list of registers per reference, in order.
    CallResult<std::vector<std::vector<std::uint16_t>>> read_file_records(
        std::span<const protocol::FileRecordRef> references);
    CallResult<Done> write_file_records(std::span<const FileRecordWrite> records);
    CallResult<Done> mask_write_register(std::uint16_t address, std::uint16_t and_mask,
                                         std::uint16_t or_mask);
    CallResult<std::vector<std::uint16_t>> read_write_multiple_registers(
        std::uint16_t read_address, std::uint16_t read_count, std::uint16_t write_address,
        std::span<const std::uint16_t> values);
    CallResult<std::vector<std::uint16_t>> read_fifo_queue(std::uint16_t address);
    // Read codes 01..03 follow "more follows" across transactions until the device has sent
    // every object; code 04 reads `object_id` alone.
    CallResult<DeviceIdentification> read_device_identification(std::uint8_t read_code,
                                                                std::uint8_t object_id = 0);
    CallResult<ObjectMessageAnswer> object_messaging(const ObjectMessage& message);
    // Any PDU; the answer PDU comes back as it is (its frame checked, its body not), exceptions
    // included, for the caller to decode.
    CallResult<std::vector<std::uint8_t>> raw(std::span<const std::uint8_t> pdu);

    Transactor& transactor() { return transactor_; }

  private:
    template <class Answer, class Extract>
    auto call(const protocol::Request& request, Extract extract)
        -> CallResult<decltype(extract(std::declval<const Answer&>()))>;
    CallResult<std::vector<bool>> read_bits(protocol::FunctionCode function, std::uint16_t address,
                                            std::uint16_t count);
    CallResult<std::vector<std::uint16_t>> read_registers(protocol::FunctionCode function,
                                                          std::uint16_t address,
                                                          std::uint16_t count);

    Transactor& transactor_;
};

}  // namespace mblab::client
