#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>

// What the Modbus application protocol spec says of an answer beyond its byte pattern: the
// catalogue's patterns pin the fields a case is about, these rules check every other field of
// every normal answer with the decoder the client uses, so a case fails on any field the spec
// fixes, and the failure names that field.
namespace mblab::conformance {

// Why `answer_pdu` breaks the spec as an answer to `request_pdu`, naming the field; nothing when
// it does not, when the answer is an exception, or when the request itself is not a valid one
// (the cases that send broken requests judge their answers by pattern alone).
std::optional<std::string> answer_rule_broken(std::span<const std::uint8_t> request_pdu,
                                              std::span<const std::uint8_t> answer_pdu);

}  // namespace mblab::conformance
