#include "robustness/fuzz_case.hpp"

#include <array>

namespace mblab::robustness {

namespace {

struct ClassRow {
    std::string_view name;
    std::string_view expectation;
};

// Indexed by BadInput.
constexpr std::array<ClassRow, kBadInputCount> kClasses{{
    {"protocol-id", "discarded or closed; the device keeps serving"},
    {"mbap-length", "a bounded wait, then exception 03 or a close; never out of step"},
    {"oversize", "rejected or closed"},
    {"truncated", "an exception or a discard, never a read past the frame"},
    {"quantity", "exception 03"},
    {"byte-count", "exception 03"},
    {"address-wrap", "exception 02 (or 03)"},
    {"unknown-function", "exception 01"},
    {"sub-function", "exception 01 or 03 for what is not served"},
    {"file-record", "an exception for sub-requests that overrun the frame"},
    {"unit-id", "answered, ignored or exception 0A/0B; the device keeps serving"},
    {"split-frame", "answered once the frame is whole, or closed after a bounded wait"},
    {"partial-header", "an idle timer closes it; other connections are served meanwhile"},
    {"pipelined", "each answered with its own transaction id, or 06 busy"},
    {"many-connections", "served, or the oldest idle connection closed"},
    {"slow-reader", "the slow reader held or closed; other connections served meanwhile"},
    {"half-open", "an idle timer closes them; other connections served meanwhile"},
    {"flood", "each answered or 06 busy; every acknowledged write kept"},
    {"boundary", "answered, or the exception the limits call for"},
    {"frame-check", "discarded without an answer"},
    {"short-frame", "discarded without an answer"},
    {"line-gap", "both halves discarded (or answered once whole, if the gap is tolerated)"},
    {"noise", "discarded; the next whole frame is answered"},
    {"ascii-text", "discarded; the next ':' starts a new frame"},
    {"pairwise", "answered, the exception the fields call for, a discard or a close"},
    {"mutation", "answered, an exception, a discard or a close"},
}};

}  // namespace

std::string_view class_name(BadInput kind) {
    return kClasses[static_cast<std::size_t>(kind)].name;
}

std::string_view class_expectation(BadInput kind) {
    return kClasses[static_cast<std::size_t>(kind)].expectation;
}

std::optional<BadInput> class_named(std::string_view name) {
    for (std::size_t i = 0; i < kClasses.size(); ++i) {
        if (kClasses[i].name == name) return static_cast<BadInput>(i);
    }
    return std::nullopt;
}

std::vector<std::uint8_t> mbap_frame(std::uint16_t transaction, std::uint8_t unit,
                                     std::span<const std::uint8_t> pdu, std::uint16_t protocol,
                                     std::optional<std::uint16_t> length) {
    const auto field = length.value_or(static_cast<std::uint16_t>(pdu.size() + 1));
    // Reserved and appended rather than initialised and extended: g++ 12 takes the latter for an
    // out-of-bounds copy (-Warray-bounds).
    std::vector<std::uint8_t> out;
    out.reserve(7 + pdu.size());
    for (std::uint16_t word : {transaction, protocol, field}) {
        out.push_back(static_cast<std::uint8_t>(word >> 8));
        out.push_back(static_cast<std::uint8_t>(word));
    }
    out.push_back(unit);
    for (std::uint8_t byte : pdu)
        out.push_back(byte);
    return out;
}

}  // namespace mblab::robustness
