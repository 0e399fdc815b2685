#include "cli/pdu_text.hpp"

#include <fmt/core.h>

#include <variant>

#include "cli/number_text.hpp"
#include "client/hex_text.hpp"
#include "protocol/request.hpp"
#include "protocol/response.hpp"

namespace mblab::cli {

namespace {

using namespace protocol;

std::string registers_text(RegisterView values) {
    std::string text;
    for (std::size_t i = 0; i < values.size(); ++i) {
        text += fmt::format("{}0x{:04X}", i == 0 ? "" : " ", values[i]);
    }
    return text;
}

std::string bits_text(BitView bits) {
    std::string text;
    for (std::size_t i = 0; i < bits.size(); ++i)
        text += fmt::format("{}{}", i == 0 ? "" : " ", int{bits[i]});
    return text;
}

std::string data_text(std::span<const std::uint8_t> data) {
    return data.empty() ? "none" : client::hex_bytes(data);
}

std::string diagnostic_text(std::uint16_t sub, std::span<const std::uint8_t> data) {
    return fmt::format("sub-function 0x{:04X} ({}), data {}", sub, diagnostic_sub_name(sub),
                       data_text(data));
}

std::string object_messaging_text(const auto& m) {
    return fmt::format(
        "fragment byte count {}, fragment protocol 0x{:02X}, class 0x{:04X}, instance 0x{:04X}, "
        "service code 0x{:04X}",
        m.fragment_byte_count, m.fragment_protocol, m.class_id, m.instance_id, m.service_code);
}

std::string read_device_id_code_text(std::uint8_t code) {
    switch (code) {
        case 1:
            return "01 (basic)";
        case 2:
            return "02 (regular)";
        case 3:
            return "03 (extended)";
        case 4:
            return "04 (one object)";
        default:
            return fmt::format("{:02X}", code);
    }
}

struct RequestFields {
    std::string operator()(const ReadBitsRequest& r) const { return range(r); }
    std::string operator()(const ReadRegistersRequest& r) const { return range(r); }
    std::string operator()(const WriteSingleCoilRequest& r) const {
        return fmt::format("output address {}, output value 0x{:04X} ({})", address_text(r.address),
                           r.value, r.on() ? "on" : "off");
    }
    std::string operator()(const WriteSingleRegisterRequest& r) const {
        return fmt::format("register address {}, register value 0x{:04X} ({})",
                           address_text(r.address), r.value, r.value);
    }
    std::string operator()(const ReadExceptionStatusRequest&) const { return "no fields"; }
    std::string operator()(const DiagnosticsRequest& r) const {
        return diagnostic_text(r.sub_function, r.data);
    }
    std::string operator()(const GetCommEventCounterRequest&) const { return "no fields"; }
    std::string operator()(const GetCommEventLogRequest&) const { return "no fields"; }
    std::string operator()(const WriteMultipleCoilsRequest& r) const {
        return fmt::format("{}, byte count {}, outputs {}", range(r), r.values.bytes().size(),
                           bits_text(r.values));
    }
    std::string operator()(const WriteMultipleRegistersRequest& r) const {
        return fmt::format("{}, byte count {}, registers {}", range(r), r.values.bytes().size(),
                           registers_text(r.values));
    }
    std::string operator()(const ReportServerIdRequest&) const { return "no fields"; }
    std::string operator()(const ReadFileRecordRequest& r) const {
        std::string text = fmt::format("byte count {}", r.sub_requests.size());
        for (std::size_t i = 0; i < r.count(); ++i) {
            const auto ref = r.at(i);
            text += fmt::format("; file {} record {} length {}", ref.file, ref.record, ref.length);
        }
        return text;
    }
    std::string operator()(const WriteFileRecordRequest& r) const {
        std::string text = fmt::format("byte count {}", r.sub_requests.size());
        std::size_t offset = 0;
        FileRecordData record;
        while (r.next(offset, record)) {
            text += fmt::format("; file {} record {} registers {}", record.ref.file,
                                record.ref.record, registers_text(record.data));
        }
        return text;
    }
    std::string operator()(const MaskWriteRegisterRequest& r) const {
        return fmt::format("reference address {}, and mask 0x{:04X}, or mask 0x{:04X}",
                           address_text(r.address), r.and_mask, r.or_mask);
    }
    std::string operator()(const ReadWriteMultipleRegistersRequest& r) const {
        return fmt::format(
            "read starting address {}, quantity to read {}, write starting address {}, quantity "
            "to write {}, byte count {}, registers {}",
            address_text(r.read_address), r.read_quantity, address_text(r.write_address),
            r.write_quantity, r.values.bytes().size(), registers_text(r.values));
    }
    std::string operator()(const ReadFifoQueueRequest& r) const {
        return fmt::format("FIFO pointer address {}", address_text(r.address));
    }
    std::string operator()(const ReadDeviceIdRequest& r) const {
        return fmt::format("MEI type 0x0E, read device id code {}, object id 0x{:02X}",
                           read_device_id_code_text(r.read_code), r.object_id);
    }
    std::string operator()(const EncapsulatedRequest& r) const {
        return fmt::format("MEI type 0x{:02X}, data {}", r.mei_type, data_text(r.data));
    }
    std::string operator()(const ObjectMessagingRequest& r) const {
        return fmt::format("{}, parameters {}", object_messaging_text(r), data_text(r.parameters));
    }
    std::string operator()(const RawRequest& r) const {
        return fmt::format("data {}", data_text(r.data));
    }

    template <class Message>
    static std::string range(const Message& r) {
        return fmt::format("starting address {}, quantity {}", address_text(r.address), r.quantity);
    }
};

struct ResponseFields {
    std::string operator()(const ReadBitsResponse& r) const {
        return fmt::format("byte count {}, bits {}", r.packed.size(),
                           bits_text(BitView(r.packed, r.packed.size() * 8)));
    }
    std::string operator()(const ReadRegistersResponse& r) const { return registers(r.values); }
    std::string operator()(const WriteSingleCoilResponse& r) const {
        return RequestFields{}(WriteSingleCoilRequest{r.address, r.value});
    }
    std::string operator()(const WriteSingleRegisterResponse& r) const {
        return RequestFields{}(WriteSingleRegisterRequest{r.address, r.value});
    }
    std::string operator()(const ReadExceptionStatusResponse& r) const {
        return fmt::format("output data 0x{:02X}", r.status);
    }
    std::string operator()(const DiagnosticsResponse& r) const {
        return diagnostic_text(r.sub_function, r.data);
    }
    std::string operator()(const GetCommEventCounterResponse& r) const {
        return fmt::format("status 0x{:04X}, event count {}", r.status, r.event_count);
    }
    std::string operator()(const GetCommEventLogResponse& r) const {
        return fmt::format(
            "byte count {}, status 0x{:04X}, event count {}, message count {}, "
            "events {}",
            r.events.size() + 6, r.status, r.event_count, r.message_count, data_text(r.events));
    }
    std::string operator()(const WriteMultipleCoilsResponse& r) const {
        return RequestFields::range(r);
    }
    std::string operator()(const WriteMultipleRegistersResponse& r) const {
        return RequestFields::range(r);
    }
    std::string operator()(const ReportServerIdResponse& r) const {
        return fmt::format("byte count {}, data {}", r.data.size(), data_text(r.data));
    }
    std::string operator()(const ReadFileRecordResponse& r) const {
        std::string text = fmt::format("data length {}", r.sub_responses.size());
        std::size_t offset = 0;
        RegisterView data;
        while (r.next(offset, data))
            text += fmt::format("; record {}", registers_text(data));
        return text;
    }
    std::string operator()(const WriteFileRecordResponse& r) const {
        return RequestFields{}(WriteFileRecordRequest{r.sub_requests});
    }
    std::string operator()(const MaskWriteRegisterResponse& r) const {
        return RequestFields{}(MaskWriteRegisterRequest{r.address, r.and_mask, r.or_mask});
    }
    std::string operator()(const ReadWriteMultipleRegistersResponse& r) const {
        return registers(r.values);
    }
    std::string operator()(const ReadFifoQueueResponse& r) const {
        return fmt::format("byte count {}, FIFO count {}, registers {}",
                           r.values.bytes().size() + 2, r.values.size(), registers_text(r.values));
    }
    std::string operator()(const ReadDeviceIdResponse& r) const {
        std::string text = fmt::format(
            "MEI type 0x0E, read device id code {}, conformity level 0x{:02X}, more follows "
            "0x{:02X}, next object id 0x{:02X}, number of objects {}",
            read_device_id_code_text(r.read_code), r.conformity_level, r.more_follows,
            r.next_object_id, r.object_count);
        std::size_t offset = 0;
        DeviceIdObject object;
        while (r.next(offset, object)) {
            text += fmt::format("; object 0x{:02X} \"{}\"", object.id, object.text());
        }
        return text;
    }
    std::string operator()(const EncapsulatedResponse& r) const {
        return fmt::format("MEI type 0x{:02X}, data {}", r.mei_type, data_text(r.data));
    }
    std::string operator()(const ObjectMessagingResponse& r) const {
        return fmt::format("{}, error code 0x{:04X}, parameters {}", object_messaging_text(r),
                           r.error_code, data_text(r.parameters));
    }
    std::string operator()(const ExceptionResponse& r) const {
        return fmt::format("exception code {:02X} ({})", static_cast<unsigned>(r.code),
                           exception_name(r.code));
    }
    std::string operator()(const RawResponse& r) const {
        return fmt::format("data {}", data_text(r.data));
    }

    static std::string registers(RegisterView values) {
        return fmt::format("byte count {}, registers {}", values.bytes().size(),
                           registers_text(values));
    }
};

std::string function_head(std::uint8_t code) {
    if (code & kExceptionBit) {
        const auto request = static_cast<std::uint8_t>(code & ~kExceptionBit);
        if (!is_public_function(request)) {
            return fmt::format("function 0x{:02X} exception to function 0x{:02X}", code, request);
        }
        return fmt::format("function 0x{:02X} exception to {}", code, function_name(request));
    }
    if (!is_public_function(code)) return fmt::format("function 0x{:02X}", code);
    return fmt::format("function 0x{:02X} {}", code, function_name(code));
}

template <class Decoded, class Fields>
std::string describe(std::span<const std::uint8_t> pdu, const Decoded& decoded, Fields fields) {
    if (pdu.empty()) return "empty PDU";
    std::string head = function_head(pdu[0]);
    if (!decoded) {
        return fmt::format("{}: does not decode: {}: {}", head, decoded.error().field,
                           decoded.error().reason);
    }
    return head + ": " + std::visit(fields, *decoded);
}

}  // namespace

std::string describe_request_pdu(std::span<const std::uint8_t> pdu) {
    return describe(pdu, decode_request(pdu), RequestFields{});
}

std::string describe_response_pdu(std::span<const std::uint8_t> pdu) {
    return describe(pdu, decode_response(pdu), ResponseFields{});
}

}  // namespace mblab::cli
