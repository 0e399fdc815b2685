#pragma once

#include <cxxabi.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <ostream>
#include <span>
#include <string>
#include <type_traits>
#include <typeinfo>
#include <variant>
#include <vector>

#include "pdu_test_support.hpp"
#include "protocol/request.hpp"
#include "protocol/response.hpp"
#include "support/hex.hpp"

// A decoded message as one line of text, its type then every field: "ReadBitsRequest function=1
// address=19 quantity=19". A table row states all an example decodes to in one string, and a
// mismatch shows every field at once.
namespace mblab::protocol::testing {

class FieldsText {
  public:
    template <class Integer>
    requires std::is_integral_v<Integer> || std::is_enum_v<Integer>
    void add(const char* name, Integer value) {
        add_text(name, std::to_string(static_cast<long long>(value)));
    }
    void add(const char* name, std::span<const std::uint8_t> bytes) {
        add_text(name, "[" + mblab::test::to_hex(bytes) + "]");
    }
    // Registers as four hex digits each.
    void add(const char* name, const RegisterView& words) {
        std::string out;
        for (std::size_t i = 0; i < words.size(); ++i) {
            char digits[6];
            std::snprintf(digits, sizeof digits, "%s%04X", i == 0 ? "" : " ", words[i]);
            out += digits;
        }
        add_text(name, "[" + out + "]");
    }
    // Bits in wire order, the first coil first.
    void add(const char* name, const BitView& bits) {
        std::string out;
        for (std::size_t i = 0; i < bits.size(); ++i)
            out += bits[i] ? '1' : '0';
        add_text(name, out);
    }
    void add_text(const char* name, const std::string& value) {
        text_ += " " + std::string(name) + "=" + value;
    }
    std::string str() const { return text_; }

  private:
    std::string text_;
};

// "ReadBitsRequest" for mblab::protocol::ReadBitsRequest.
template <class Message>
std::string type_name() {
    int status = 0;
    const std::unique_ptr<char, void (*)(void*)> full(
        abi::__cxa_demangle(typeid(Message).name(), nullptr, nullptr, &status), std::free);
    const std::string name = status == 0 ? full.get() : typeid(Message).name();
    return name.substr(name.rfind("::") + 2);
}

// One printer for every message type: each field a message has is printed under its own name,
// in this order. File records and device id objects are walked by their own tests.
template <class Message>
std::string fields_text(const Message& m) {
    FieldsText out;
#define MBLAB_FIELD(member) \
    if constexpr (requires { m.member; }) out.add(#member, m.member)
    MBLAB_FIELD(function);
    MBLAB_FIELD(mei_type);
    MBLAB_FIELD(read_code);
    MBLAB_FIELD(object_id);
    MBLAB_FIELD(sub_function);
    MBLAB_FIELD(status);
    MBLAB_FIELD(event_count);
    MBLAB_FIELD(message_count);
    MBLAB_FIELD(events);
    MBLAB_FIELD(address);
    MBLAB_FIELD(quantity);
    MBLAB_FIELD(read_address);
    MBLAB_FIELD(read_quantity);
    MBLAB_FIELD(write_address);
    MBLAB_FIELD(write_quantity);
    MBLAB_FIELD(value);
    MBLAB_FIELD(and_mask);
    MBLAB_FIELD(or_mask);
    MBLAB_FIELD(fragment_byte_count);
    MBLAB_FIELD(fragment_protocol);
    MBLAB_FIELD(class_id);
    MBLAB_FIELD(instance_id);
    MBLAB_FIELD(service_code);
    MBLAB_FIELD(error_code);
    MBLAB_FIELD(code);
    MBLAB_FIELD(conformity_level);
    MBLAB_FIELD(more_follows);
    MBLAB_FIELD(next_object_id);
    MBLAB_FIELD(object_count);
    MBLAB_FIELD(packed);
    MBLAB_FIELD(values);
    MBLAB_FIELD(data);
    MBLAB_FIELD(parameters);
    MBLAB_FIELD(sub_requests);
#undef MBLAB_FIELD
    if constexpr (requires { m.on(); }) out.add("on", m.on());
    return type_name<Message>() + out.str();
}

template <class... Messages>
std::string fields_text(const std::variant<Messages...>& message) {
    return std::visit([](const auto& m) { return fields_text(m); }, message);
}

// One example: `pdu` decodes to a message whose fields_text is `fields`, and that message
// encodes back to `pdu`, so a message built from those fields does too.
struct FieldsCase {
    std::string name;
    std::string pdu;
    std::string fields;
    bool response = false;  // decoded as a response, else as a request
};

inline void PrintTo(const FieldsCase& row, std::ostream* out) {
    *out << row.name << " [" << row.pdu << "]";
}

inline std::string fields_case_name(const ::testing::TestParamInfo<FieldsCase>& info) {
    return info.param.name;
}

// The rows of a table of responses.
template <std::size_t N>
std::vector<FieldsCase> as_responses(const FieldsCase (&rows)[N]) {
    std::vector<FieldsCase> out(rows, rows + N);
    for (auto& row : out)
        row.response = true;
    return out;
}

// Request and response tables instantiate this one test (test_request_fields.cpp defines it).
class PduFields : public ::testing::TestWithParam<FieldsCase> {};

template <class Message>
void expect_fields(const FieldsCase& row,
                   Result<Message> (*decode)(std::span<const std::uint8_t>)) {
    expect_round_trip(row.pdu, decode);
    const auto pdu = mblab::test::hex(row.pdu);
    const auto decoded = decode(pdu);
    ASSERT_TRUE(decoded.ok());
    EXPECT_EQ(fields_text(*decoded), row.fields);
}

}  // namespace mblab::protocol::testing
