#include "conformance/plain_requests.hpp"

#include "protocol/request_template.hpp"

// The requests themselves are the sample and harmless columns of protocol's request templates.
namespace mblab::conformance {

namespace {

using protocol::RequestTemplate;

// The template of a function whose sample writes a value FC 01 or FC 03 can read back.
const RequestTemplate* written_back(std::uint8_t function) {
    const RequestTemplate* request = protocol::find_template(function);
    return request != nullptr && request->value_form != protocol::ValueForm::None ? request
                                                                                  : nullptr;
}

// The read of the table a write-back writes: the function that reads a quantity of it.
const RequestTemplate* reader_of(protocol::DataTable table) {
    for (const RequestTemplate& request : protocol::request_templates()) {
        const auto code = static_cast<std::uint8_t>(request.code);
        if (request.table == table && !protocol::writes(code) &&
            protocol::field_with(request, protocol::FieldRole::Quantity) != nullptr) {
            return &request;
        }
    }
    return nullptr;
}

}  // namespace

std::optional<std::vector<std::uint8_t>> plain_request_pdu(std::uint8_t function) {
    return protocol::sample_request(function);
}

std::span<const std::uint8_t> functions_with_plain_requests() {
    static const auto codes = [] {
        std::vector<std::uint8_t> out;
        for (const RequestTemplate& request : protocol::request_templates()) {
            if (!request.sample.empty()) out.push_back(static_cast<std::uint8_t>(request.code));
        }
        return out;
    }();
    return codes;
}

std::optional<std::vector<std::uint8_t>> harmless_request_pdu(std::uint8_t function) {
    return protocol::harmless_request(function);
}

std::optional<std::vector<std::uint8_t>> read_before_write_back(std::uint8_t function) {
    const RequestTemplate* write = written_back(function);
    const RequestTemplate* read = write != nullptr ? reader_of(write->table) : nullptr;
    if (read == nullptr) return std::nullopt;
    return protocol::sample_request(static_cast<std::uint8_t>(read->code));
}

std::optional<std::vector<std::uint8_t>> write_back_pdu(std::uint8_t function,
                                                        std::span<const std::uint8_t> read_answer) {
    const RequestTemplate* write = written_back(function);
    const RequestTemplate* read = write != nullptr ? reader_of(write->table) : nullptr;
    if (read == nullptr) return std::nullopt;
    // The read asks for one bit or one register: function, byte count, then 1 or 2 bytes.
    const std::size_t value_bytes = write->table == protocol::DataTable::Coils ? 1 : 2;
    if (read_answer.size() != 2 + value_bytes ||
        read_answer[0] != static_cast<std::uint8_t>(read->code) || read_answer[1] != value_bytes) {
        return std::nullopt;
    }
    auto pdu = protocol::sample_request(function);
    const bool on = (read_answer[2] & 0x01) != 0;
    std::uint8_t* value = pdu->data() + write->value_at;
    switch (write->value_form) {
        case protocol::ValueForm::CoilWord:
            value[0] = on ? 0xFF : 0x00;
            value[1] = 0x00;
            break;
        case protocol::ValueForm::PackedBits:
            value[0] = on ? 0x01 : 0x00;
            break;
        default:  // a register
            value[0] = read_answer[2];
            value[1] = read_answer[3];
            break;
    }
    return pdu;
}

}  // namespace mblab::conformance
