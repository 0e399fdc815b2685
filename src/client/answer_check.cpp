#include "client/answer_check.hpp"

#include <algorithm>
#include <cstdio>
#include <variant>

#include "client/hex_text.hpp"
#include "protocol/limits.hpp"

namespace mblab::client {

namespace {

using namespace protocol;

std::string plural(std::size_t count, const char* one, const char* many) {
    return std::to_string(count) + " " + (count == 1 ? one : many);
}

std::string echo_differs(const char* what) {
    return std::string("the echoed ") + what + " differs from the request";
}

bool same_bytes(std::span<const std::uint8_t> a, std::span<const std::uint8_t> b) {
    return std::equal(a.begin(), a.end(), b.begin(), b.end());
}

// One overload per request type; each finds the answer type it expects.
class Judge {
  public:
    explicit Judge(const Response& response) : response_(response) {}
    using Verdict = std::optional<std::string>;

    Verdict operator()(const ReadBitsRequest& request) const {
        const auto* answer = as<ReadBitsResponse>();
        if (answer == nullptr) return other();
        const std::size_t expected = (request.quantity + 7U) / 8U;
        if (answer->packed.size() != expected) {
            return plural(answer->packed.size(), "byte", "bytes") + " of bits, expected " +
                   std::to_string(expected) + " for " + plural(request.quantity, "bit", "bits");
        }
        return std::nullopt;
    }
    Verdict operator()(const ReadRegistersRequest& request) const {
        const auto* answer = as<ReadRegistersResponse>();
        if (answer == nullptr) return other();
        return register_count(answer->values.size(), request.quantity);
    }
    Verdict operator()(const WriteSingleCoilRequest& request) const {
        const auto* answer = as<WriteSingleCoilResponse>();
        if (answer == nullptr) return other();
        return echo(answer->address == request.address && answer->value == request.value,
                    "address and value");
    }
    Verdict operator()(const WriteSingleRegisterRequest& request) const {
        const auto* answer = as<WriteSingleRegisterResponse>();
        if (answer == nullptr) return other();
        return echo(answer->address == request.address && answer->value == request.value,
                    "address and value");
    }
    Verdict operator()(const ReadExceptionStatusRequest&) const {
        return kind<ReadExceptionStatusResponse>();
    }
    Verdict operator()(const DiagnosticsRequest& request) const {
        const auto* answer = as<DiagnosticsResponse>();
        if (answer == nullptr) return other();
        if (answer->sub_function != request.sub_function) {
            return "sub-function is " + hex16(answer->sub_function) + ", expected " +
                   hex16(request.sub_function);
        }
        if (diagnostic_answer_echoes(request.sub_function) &&
            !same_bytes(answer->data, request.data)) {
            return echo_differs("data");
        }
        return std::nullopt;
    }
    Verdict operator()(const GetCommEventCounterRequest&) const {
        return kind<GetCommEventCounterResponse>();
    }
    Verdict operator()(const GetCommEventLogRequest&) const {
        return kind<GetCommEventLogResponse>();
    }
    Verdict operator()(const WriteMultipleCoilsRequest& request) const {
        return range_echo<WriteMultipleCoilsResponse>(request);
    }
    Verdict operator()(const WriteMultipleRegistersRequest& request) const {
        return range_echo<WriteMultipleRegistersResponse>(request);
    }
    Verdict operator()(const ReportServerIdRequest&) const {
        return kind<ReportServerIdResponse>();
    }
    Verdict operator()(const ReadFileRecordRequest& request) const {
        const auto* answer = as<ReadFileRecordResponse>();
        if (answer == nullptr) return other();
        std::size_t offset = 0;
        std::size_t index = 0;
        RegisterView data;
        while (answer->next(offset, data)) {
            if (index == request.count()) break;
            const auto wanted = request.at(index).length;
            if (data.size() != wanted) {
                return "record " + std::to_string(index + 1) + " holds " +
                       plural(data.size(), "register", "registers") + ", expected " +
                       std::to_string(wanted);
            }
            ++index;
        }
        std::size_t answered = index;
        while (answer->next(offset, data))
            ++answered;
        if (answered != request.count()) {
            return plural(answered, "record", "records") + " in the answer, expected " +
                   std::to_string(request.count());
        }
        return std::nullopt;
    }
    Verdict operator()(const WriteFileRecordRequest& request) const {
        const auto* answer = as<WriteFileRecordResponse>();
        if (answer == nullptr) return other();
        return echo(same_bytes(answer->sub_requests, request.sub_requests), "records");
    }
    Verdict operator()(const MaskWriteRegisterRequest& request) const {
        const auto* answer = as<MaskWriteRegisterResponse>();
        if (answer == nullptr) return other();
        return echo(answer->address == request.address && answer->and_mask == request.and_mask &&
                        answer->or_mask == request.or_mask,
                    "address and masks");
    }
    Verdict operator()(const ReadWriteMultipleRegistersRequest& request) const {
        const auto* answer = as<ReadWriteMultipleRegistersResponse>();
        if (answer == nullptr) return other();
        return register_count(answer->values.size(), request.read_quantity);
    }
    Verdict operator()(const ReadFifoQueueRequest&) const { return kind<ReadFifoQueueResponse>(); }
    Verdict operator()(const ReadDeviceIdRequest& request) const {
        if (const auto* other_mei = as<EncapsulatedResponse>()) {
            return "MEI type is " + hex8(other_mei->mei_type) + ", expected 0x0E";
        }
        const auto* answer = as<ReadDeviceIdResponse>();
        if (answer == nullptr) return other();
        if (answer->read_code != request.read_code) {
            return "read device id code is " + hex8(answer->read_code) + ", expected " +
                   hex8(request.read_code);
        }
        DeviceIdObject object;
        std::size_t offset = 0;
        if (request.read_code == limits::kReadDeviceIdIndividual && answer->next(offset, object) &&
            object.id != request.object_id) {
            return "object id is " + hex8(object.id) + ", expected " + hex8(request.object_id);
        }
        return std::nullopt;
    }
    Verdict operator()(const EncapsulatedRequest&) const { return std::nullopt; }
    Verdict operator()(const ObjectMessagingRequest& request) const {
        const auto* answer = as<ObjectMessagingResponse>();
        if (answer == nullptr) return other();
        if (answer->class_id != request.class_id || answer->instance_id != request.instance_id) {
            return "object class " + hex16(answer->class_id) + " instance " +
                   hex16(answer->instance_id) + ", expected class " + hex16(request.class_id) +
                   " instance " + hex16(request.instance_id);
        }
        return std::nullopt;
    }
    Verdict operator()(const RawRequest&) const { return std::nullopt; }

  private:
    template <class Answer>
    const Answer* as() const {
        return std::get_if<Answer>(&response_);
    }
    template <class Answer>
    Verdict kind() const {
        return as<Answer>() != nullptr ? std::nullopt : other();
    }
    Verdict other() const { return std::string("the answer is not of the request's kind"); }
    static Verdict echo(bool same, const char* what) {
        return same ? std::nullopt : Verdict(echo_differs(what));
    }
    static Verdict register_count(std::size_t got, std::size_t wanted) {
        if (got == wanted) return std::nullopt;
        return plural(got, "register", "registers") + ", expected " + std::to_string(wanted);
    }
    template <class Answer, class Request>
    Verdict range_echo(const Request& request) const {
        const auto* answer = as<Answer>();
        if (answer == nullptr) return other();
        return echo(answer->address == request.address && answer->quantity == request.quantity,
                    "address and quantity");
    }

    const Response& response_;
};

struct Span {
    std::uint32_t first = 0;
    std::uint32_t count = 0;
};

// The addresses a request names, for exception 02; none for requests without a data range.
std::optional<Span> data_span(const Request& request) {
    return std::visit(
        [](const auto& r) -> std::optional<Span> {
            using R = std::decay_t<decltype(r)>;
            if constexpr (requires {
                              r.address;
                              r.quantity;
                          }) {
                return Span{r.address, r.quantity};
            } else if constexpr (std::is_same_v<R, WriteSingleCoilRequest> ||
                                 std::is_same_v<R, WriteSingleRegisterRequest> ||
                                 std::is_same_v<R, MaskWriteRegisterRequest>) {
                return Span{r.address, 1};
            } else {
                return std::nullopt;
            }
        },
        request);
}

// "0x0001" or "0x0001..0x0009"
std::string range_text(const Span& span) {
    if (span.count == 1) return hex16(span.first);
    return hex16(span.first) + ".." + hex16(span.first + span.count - 1);
}

// "0x0001 is not on", "0x0001..0x0009 are not all writable on": the subject of the sentence.
std::string span_text(const Span& span, const char* what) {
    return range_text(span) + (span.count == 1 ? " is not " : " are not all ") + what;
}

bool is_write(const Request& request) {
    return std::holds_alternative<WriteSingleCoilRequest>(request) ||
           std::holds_alternative<WriteSingleRegisterRequest>(request) ||
           std::holds_alternative<WriteMultipleCoilsRequest>(request) ||
           std::holds_alternative<WriteMultipleRegistersRequest>(request) ||
           std::holds_alternative<MaskWriteRegisterRequest>(request);
}

std::string address_meaning(const Request& request) {
    if (const auto* rw = std::get_if<ReadWriteMultipleRegistersRequest>(&request)) {
        return "the read range " + range_text({rw->read_address, rw->read_quantity}) +
               " or the write range " + range_text({rw->write_address, rw->write_quantity}) +
               " is not on this device";
    }
    if (const auto* fifo = std::get_if<ReadFifoQueueRequest>(&request)) {
        return hex16(fifo->address) + " is not a FIFO queue on this device";
    }
    if (const auto* id = std::get_if<ReadDeviceIdRequest>(&request)) {
        return "object " + hex8(id->object_id) + " is not on this device";
    }
    if (std::holds_alternative<ReadFileRecordRequest>(request) ||
        std::holds_alternative<WriteFileRecordRequest>(request)) {
        return "a file or record is not on this device";
    }
    if (auto span = data_span(request)) {
        return span_text(*span, is_write(request) ? "writable " : "") + "on this device";
    }
    return std::string(exception_meaning(ExceptionCode::IllegalDataAddress));
}

std::string function_meaning(const Request& request) {
    const std::uint8_t function = function_of(request);
    std::string text = "the device does not support function " + hex8(function);
    if (is_public_function(function)) text += " (" + std::string(function_name(function)) + ")";
    if (const auto* diag = std::get_if<DiagnosticsRequest>(&request)) {
        text += " sub-function " + hex16(diag->sub_function);
    }
    return text;
}

}  // namespace

std::optional<std::string> answer_mismatch(const Request& request, const Response& response) {
    if (std::holds_alternative<ExceptionResponse>(response)) return std::nullopt;
    return std::visit(Judge(response), request);
}

std::string describe_exception(const Request& request, ExceptionCode code) {
    char head[16];
    std::snprintf(head, sizeof head, "exception %02X ", static_cast<unsigned>(code));
    std::string meaning;
    switch (code) {
        case ExceptionCode::IllegalFunction:
            meaning = function_meaning(request);
            break;
        case ExceptionCode::IllegalDataAddress:
            meaning = address_meaning(request);
            break;
        default:
            meaning = exception_meaning(code);
            break;
    }
    return head + std::string(exception_name(code)) + ": " + meaning;
}

}  // namespace mblab::client
