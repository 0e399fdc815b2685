#include "client/client.hpp"

#include <array>
#include <utility>

#include "client/answer_check.hpp"
#include "client/hex_text.hpp"
#include "protocol/limits.hpp"

namespace mblab::client {

namespace {

using namespace protocol;

// Room for the largest PDU, and a little more: a request just over [APP]'s limits (2000 coils to
// write make a 256-byte PDU) still encodes, so that the codec's check in call() names the field at
// fault ("quantity: must be 1..1968") instead of saying the request does not fit.
constexpr std::size_t kRoomOverLimit = 8;
using PduBuffer = std::array<std::uint8_t, limits::kMaxPdu + kRoomOverLimit>;

ClientError invalid(std::string message) {
    return {ErrorKind::Invalid, std::move(message), std::nullopt};
}

// A quantity over [APP]'s limit, said the way the codec says it for the fields it can check.
ClientError over_limit(const char* function, const char* field, std::size_t got, unsigned max) {
    return invalid(std::string(function) + ": " + field + ": must be 1.." + std::to_string(max) +
                   " (0x0001.." + hex16(max) + "), got " + std::to_string(got));
}

std::string decode_text(std::uint8_t function, const DecodeError& error) {
    return std::string(function_name(function)) + ": " + error.field + ": " + error.reason;
}

std::span<const std::uint8_t> put_registers(std::span<const std::uint16_t> values,
                                            PduBuffer& scratch) {
    WriteCursor out(scratch);
    for (auto value : values)
        out.put_u16(value);
    return out.written();
}

std::vector<std::uint16_t> registers_of(RegisterView view) {
    std::vector<std::uint16_t> values(view.size());
    for (std::size_t i = 0; i < view.size(); ++i)
        values[i] = view[i];
    return values;
}

std::vector<std::uint8_t> bytes_of(std::span<const std::uint8_t> bytes) {
    return {bytes.begin(), bytes.end()};
}

}  // namespace

template <class Answer, class Extract>
auto Client::call(const Request& request, Extract extract)
    -> CallResult<decltype(extract(std::declval<const Answer&>()))> {
    const std::uint8_t function = function_of(request);
    PduBuffer pdu{};
    WriteCursor out(pdu);
    if (!encode_request(request, out) || !out.ok()) {
        return invalid(std::string(function_name(function)) + ": the request does not fit a PDU");
    }
    // The codec's own request checks are [APP]'s limits: a request the device would have to
    // refuse is refused here, before it goes on the wire.
    if (auto checked = decode_request(out.written()); !checked) {
        return invalid(decode_text(function, checked.error()));
    }
    auto answer = transactor_.transact(out.written());
    if (!answer) return answer.error();
    auto decoded = decode_response(*answer);
    if (!decoded) {
        return ClientError{ErrorKind::BadAnswer,
                           "bad answer: " + decode_text(function, decoded.error()), std::nullopt};
    }
    if (const auto* exception = std::get_if<ExceptionResponse>(&*decoded)) {
        return ClientError{ErrorKind::Exception, describe_exception(request, exception->code),
                           exception->code};
    }
    if (auto mismatch = answer_mismatch(request, *decoded)) {
        return ClientError{ErrorKind::BadAnswer,
                           "bad answer: " + std::string(function_name(function)) + ": " + *mismatch,
                           std::nullopt};
    }
    return extract(std::get<Answer>(*decoded));
}

CallResult<std::vector<bool>> Client::read_bits(FunctionCode function, std::uint16_t address,
                                                std::uint16_t count) {
    return call<ReadBitsResponse>(ReadBitsRequest{function, address, count},
                                  [count](const ReadBitsResponse& answer) {
                                      BitView bits(answer.packed, count);
                                      std::vector<bool> values(count);
                                      for (std::size_t i = 0; i < count; ++i)
                                          values[i] = bits[i];
                                      return values;
                                  });
}

CallResult<std::vector<std::uint16_t>> Client::read_registers(FunctionCode function,
                                                              std::uint16_t address,
                                                              std::uint16_t count) {
    return call<ReadRegistersResponse>(
        ReadRegistersRequest{function, address, count},
        [](const ReadRegistersResponse& answer) { return registers_of(answer.values); });
}

CallResult<std::vector<bool>> Client::read_coils(std::uint16_t address, std::uint16_t count) {
    return read_bits(FunctionCode::ReadCoils, address, count);
}

CallResult<std::vector<bool>> Client::read_discrete_inputs(std::uint16_t address,
                                                           std::uint16_t count) {
    return read_bits(FunctionCode::ReadDiscreteInputs, address, count);
}

CallResult<std::vector<std::uint16_t>> Client::read_holding_registers(std::uint16_t address,
                                                                      std::uint16_t count) {
    return read_registers(FunctionCode::ReadHoldingRegisters, address, count);
}

CallResult<std::vector<std::uint16_t>> Client::read_input_registers(std::uint16_t address,
                                                                    std::uint16_t count) {
    return read_registers(FunctionCode::ReadInputRegisters, address, count);
}

CallResult<Done> Client::write_single_coil(std::uint16_t address, bool on) {
    return call<WriteSingleCoilResponse>(
        WriteSingleCoilRequest{address, static_cast<std::uint16_t>(on ? 0xFF00 : 0x0000)},
        [](const auto&) { return Done{}; });
}

CallResult<Done> Client::write_single_register(std::uint16_t address, std::uint16_t value) {
    return call<WriteSingleRegisterResponse>(WriteSingleRegisterRequest{address, value},
                                             [](const auto&) { return Done{}; });
}

CallResult<std::uint8_t> Client::read_exception_status() {
    return call<ReadExceptionStatusResponse>(
        ReadExceptionStatusRequest{},
        [](const ReadExceptionStatusResponse& answer) { return answer.status; });
}

CallResult<DiagnosticsAnswer> Client::diagnostics(std::uint16_t sub_function,
                                                  std::span<const std::uint8_t> data) {
    if (sub_function == static_cast<std::uint16_t>(DiagnosticSub::ForceListenOnly)) {
        return invalid("force listen only mode is never answered: use send_listen_only()");
    }
    return call<DiagnosticsResponse>(
        DiagnosticsRequest{sub_function, data}, [](const DiagnosticsResponse& answer) {
            return DiagnosticsAnswer{answer.sub_function, bytes_of(answer.data)};
        });
}

CallResult<Done> Client::send_listen_only() {
    static constexpr std::uint8_t kListenOnly[] = {0x08, 0x00, 0x04, 0x00, 0x00};
    return transactor_.send_only(kListenOnly);
}

CallResult<EventCounter> Client::get_comm_event_counter() {
    return call<GetCommEventCounterResponse>(
        GetCommEventCounterRequest{},
        [](const GetCommEventCounterResponse& answer) { return answer; });
}

CallResult<EventLog> Client::get_comm_event_log() {
    return call<GetCommEventLogResponse>(
        GetCommEventLogRequest{}, [](const GetCommEventLogResponse& answer) {
            return EventLog{answer.status, answer.event_count, answer.message_count,
                            bytes_of(answer.events)};
        });
}

CallResult<Done> Client::write_multiple_coils(std::uint16_t address,
                                              const std::vector<bool>& values) {
    PduBuffer packed{};
    const std::size_t bytes = (values.size() + 7) / 8;
    if (bytes > packed.size()) {
        return invalid("write multiple coils: " + std::to_string(values.size()) +
                       " coils do not fit a PDU");
    }
    for (std::size_t i = 0; i < values.size(); ++i) {
        if (values[i]) packed[i / 8] = static_cast<std::uint8_t>(packed[i / 8] | (1U << (i % 8)));
    }
    const auto quantity = static_cast<std::uint16_t>(values.size());
    return call<WriteMultipleCoilsResponse>(
        WriteMultipleCoilsRequest{address, quantity,
                                  BitView(std::span(packed).first(bytes), values.size())},
        [](const auto&) { return Done{}; });
}

CallResult<Done> Client::write_multiple_registers(std::uint16_t address,
                                                  std::span<const std::uint16_t> values) {
    PduBuffer scratch{};
    // Past 123 the PDU would outgrow 253 bytes before the codec could name the quantity.
    if (values.size() > limits::kMaxWriteRegisters) {
        return over_limit("write multiple registers", "quantity", values.size(),
                          limits::kMaxWriteRegisters);
    }
    const auto quantity = static_cast<std::uint16_t>(values.size());
    return call<WriteMultipleRegistersResponse>(
        WriteMultipleRegistersRequest{address, quantity,
                                      RegisterView(put_registers(values, scratch))},
        [](const auto&) { return Done{}; });
}

CallResult<std::vector<std::uint8_t>> Client::report_server_id() {
    return call<ReportServerIdResponse>(
        ReportServerIdRequest{},
        [](const ReportServerIdResponse& answer) { return bytes_of(answer.data); });
}

CallResult<std::vector<std::vector<std::uint16_t>>> Client::read_file_records(
    std::span<const FileRecordRef> references) {
    PduBuffer scratch{};
    WriteCursor subs(scratch);
    for (const auto& reference : references)
        encode_file_record_ref(subs, reference);
    if (!subs.ok()) return invalid("read file record: too many records for one request");
    return call<ReadFileRecordResponse>(ReadFileRecordRequest{subs.written()},
                                        [](const ReadFileRecordResponse& answer) {
                                            std::vector<std::vector<std::uint16_t>> records;
                                            std::size_t offset = 0;
                                            RegisterView data;
                                            while (answer.next(offset, data))
                                                records.push_back(registers_of(data));
                                            return records;
                                        });
}

CallResult<Done> Client::write_file_records(std::span<const FileRecordWrite> records) {
    PduBuffer scratch{};
    PduBuffer values{};
    WriteCursor subs(scratch);
    for (const auto& record : records) {
        if (record.values.size() * 2 > values.size()) {
            return invalid("write file record: too many registers for one request");
        }
        const auto length = static_cast<std::uint16_t>(record.values.size());
        encode_file_record_data(subs, {{record.file, record.record, length},
                                       RegisterView(put_registers(record.values, values))});
    }
    if (!subs.ok()) return invalid("write file record: too many registers for one request");
    return call<WriteFileRecordResponse>(WriteFileRecordRequest{subs.written()},
                                         [](const auto&) { return Done{}; });
}

CallResult<Done> Client::mask_write_register(std::uint16_t address, std::uint16_t and_mask,
                                             std::uint16_t or_mask) {
    return call<MaskWriteRegisterResponse>(MaskWriteRegisterRequest{address, and_mask, or_mask},
                                           [](const auto&) { return Done{}; });
}

CallResult<std::vector<std::uint16_t>> Client::read_write_multiple_registers(
    std::uint16_t read_address, std::uint16_t read_count, std::uint16_t write_address,
    std::span<const std::uint16_t> values) {
    PduBuffer scratch{};
    if (values.size() > limits::kMaxReadWriteWrite) {
        return over_limit("read/write multiple registers", "quantity to write", values.size(),
                          limits::kMaxReadWriteWrite);
    }
    const auto write_count = static_cast<std::uint16_t>(values.size());
    return call<ReadWriteMultipleRegistersResponse>(
        ReadWriteMultipleRegistersRequest{read_address, read_count, write_address, write_count,
                                          RegisterView(put_registers(values, scratch))},
        [](const ReadWriteMultipleRegistersResponse& answer) {
            return registers_of(answer.values);
        });
}

CallResult<std::vector<std::uint16_t>> Client::read_fifo_queue(std::uint16_t address) {
    return call<ReadFifoQueueResponse>(
        ReadFifoQueueRequest{address},
        [](const ReadFifoQueueResponse& answer) { return registers_of(answer.values); });
}

CallResult<DeviceIdentification> Client::read_device_identification(std::uint8_t read_code,
                                                                    std::uint8_t object_id) {
    struct Part {
        std::uint8_t conformity_level = 0;
        bool more = false;
        std::uint8_t next = 0;
        std::vector<IdentificationObject> objects;
    };
    DeviceIdentification whole;
    whole.read_code = read_code;
    std::uint8_t next = object_id;
    while (true) {
        auto part = call<ReadDeviceIdResponse>(
            ReadDeviceIdRequest{read_code, next}, [](const ReadDeviceIdResponse& answer) {
                Part out{answer.conformity_level,
                         answer.more_follows == 0xFF,
                         answer.next_object_id,
                         {}};
                DeviceIdObject object;
                std::size_t offset = 0;
                while (answer.next(offset, object)) {
                    out.objects.push_back({object.id, object.text()});
                }
                return out;
            });
        if (!part) return part.error();
        ++whole.transactions;
        whole.conformity_level = part->conformity_level;
        whole.objects.insert(whole.objects.end(), part->objects.begin(), part->objects.end());
        if (!part->more || read_code == limits::kReadDeviceIdIndividual) return whole;
        // Each answer must move forward, so a device cannot keep the client reading forever.
        if (part->objects.empty() || part->next <= part->objects.back().id) {
            return ClientError{ErrorKind::BadAnswer,
                               "bad answer: read device identification: more follows, but the "
                               "next object id " +
                                   hex8(part->next) + " does not come after the objects sent",
                               std::nullopt};
        }
        next = part->next;
    }
}

CallResult<ObjectMessageAnswer> Client::object_messaging(const ObjectMessage& message) {
    ObjectMessagingRequest request;
    request.fragment_protocol = message.fragment_protocol;
    request.class_id = message.class_id;
    request.instance_id = message.instance_id;
    request.service_code = message.service_code;
    request.parameters = message.parameters;
    return call<ObjectMessagingResponse>(request, [](const ObjectMessagingResponse& answer) {
        ObjectMessageAnswer out;
        out.fragment_protocol = answer.fragment_protocol;
        out.class_id = answer.class_id;
        out.instance_id = answer.instance_id;
        out.service_code = answer.service_code;
        out.parameters = bytes_of(answer.parameters);
        out.error_code = answer.error_code;
        return out;
    });
}

CallResult<std::vector<std::uint8_t>> Client::raw(std::span<const std::uint8_t> pdu) {
    if (pdu.empty()) return invalid("the PDU is empty: give at least a function code");
    if (pdu.size() > limits::kMaxPdu) {
        return invalid("the PDU is " + std::to_string(pdu.size()) +
                       " bytes long; the most a frame carries is 253");
    }
    return transactor_.transact(pdu);
}

}  // namespace mblab::client
