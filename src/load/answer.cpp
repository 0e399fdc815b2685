#include "load/answer.hpp"

#include <iterator>

#include "protocol/exception_code.hpp"
#include "protocol/function_code.hpp"
#include "protocol/limits.hpp"
#include "protocol/mbap_header.hpp"
#include "protocol/response.hpp"
#include "support/name_table.hpp"

namespace mblab::load {

namespace {

constexpr std::size_t kTransactionIdBytes = 2;
constexpr std::size_t kFunctionAt = protocol::limits::kMbapHeader;

std::uint16_t be16(std::span<const std::uint8_t> bytes, std::size_t at) {
    return static_cast<std::uint16_t>((bytes[at] << 8) | bytes[at + 1]);
}

struct FailureWords {
    FailureKind value;
    std::string_view key;    // JSON and metrics
    std::string_view label;  // console and HTML
};

constexpr FailureWords kFailureWords[] = {
    {FailureKind::Timeout, "timeout", "timeout"},
    {FailureKind::Malformed, "malformed", "malformed answer"},
    {FailureKind::WrongAnswer, "wrong_answer", "wrong answer"},
    {FailureKind::UnexpectedException, "exception", "unexpected exception"},
    {FailureKind::Refused, "refused", "refused connection"},
    {FailureKind::Dropped, "dropped", "dropped connection"},
};
static_assert(std::size(kFailureWords) == kFailureKinds, "one row per failure kind");

}  // namespace

std::string_view failure_key(FailureKind kind) {
    return word_of(kFailureWords, kind, &FailureWords::key, "unknown");
}

std::string_view failure_label(FailureKind kind) {
    return word_of(kFailureWords, kind, &FailureWords::label, "unknown");
}

AnswerPattern::AnswerPattern(const conformance::ResolvedPattern& pattern) {
    std::size_t pos = 0;
    for (const auto& token : pattern.tokens) {
        switch (token.kind) {
            case conformance::PatternToken::Kind::Byte:
                if (pos >= kTransactionIdBytes) {
                    literals_.push_back({static_cast<std::uint16_t>(pos), token.value});
                }
                if (pos == kFunctionAt) {
                    expects_exception_ = (token.value & protocol::kExceptionBit) != 0;
                }
                ++pos;
                break;
            case conformance::PatternToken::Kind::Length:
                length_at_ = pos;
                pos += 2;
                break;
            case conformance::PatternToken::Kind::Rest:
                open_ended_ = true;
                break;
            case conformance::PatternToken::Kind::Any:
            case conformance::PatternToken::Kind::Fact:
                ++pos;
                break;  // facts are resolved away before
        }
    }
    size_ = pos;
}

bool AnswerPattern::matches(std::span<const std::uint8_t> frame) const {
    if (open_ended_ ? frame.size() < size_ : frame.size() != size_) return false;
    for (const Literal& literal : literals_) {
        if (frame[literal.at] != literal.value) return false;
    }
    // {len} counts the bytes after it: with a fixed size that is known; after "..." it must
    // agree with the bytes that came. Either way it is what follows in the frame.
    return !length_at_ || be16(frame, *length_at_) == frame.size() - *length_at_ - 2;
}

std::optional<FailureKind> judge_answer(std::span<const AnswerPattern> alternatives,
                                        std::span<const std::uint8_t> frame) {
    bool exception_expected = false;
    for (const AnswerPattern& alternative : alternatives) {
        if (alternative.matches(frame)) return std::nullopt;
        exception_expected = exception_expected || alternative.expects_exception();
    }
    const auto answer = protocol::read_mbap_frame(frame);
    if (!answer || answer->header.protocol_id != protocol::kModbusProtocolId ||
        !protocol::decode_response(answer->pdu).ok())
        return FailureKind::Malformed;
    if ((answer->pdu[0] & protocol::kExceptionBit) != 0 && !exception_expected) {
        return FailureKind::UnexpectedException;
    }
    return FailureKind::WrongAnswer;
}

}  // namespace mblab::load
