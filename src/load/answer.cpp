#include "load/answer.hpp"

#include "protocol/exception_code.hpp"
#include "protocol/function_code.hpp"
#include "protocol/limits.hpp"
#include "protocol/mbap_header.hpp"
#include "protocol/response.hpp"

namespace mblab::load {

namespace {

constexpr std::size_t kTransactionIdBytes = 2;
constexpr std::size_t kFunctionAt = protocol::limits::kMbapHeader;

std::uint16_t be16(std::span<const std::uint8_t> bytes, std::size_t at) {
    return static_cast<std::uint16_t>((bytes[at] << 8) | bytes[at + 1]);
}

}  // namespace

std::string_view failure_key(FailureKind kind) {
    switch (kind) {
        case FailureKind::Timeout:
            return "timeout";
        case FailureKind::Malformed:
            return "malformed";
        case FailureKind::WrongAnswer:
            return "wrong_answer";
        case FailureKind::UnexpectedException:
            return "exception";
        case FailureKind::Refused:
            return "refused";
        case FailureKind::Dropped:
            return "dropped";
    }
    return "unknown";
}

std::string_view failure_label(FailureKind kind) {
    switch (kind) {
        case FailureKind::Timeout:
            return "timeout";
        case FailureKind::Malformed:
            return "malformed answer";
        case FailureKind::WrongAnswer:
            return "wrong answer";
        case FailureKind::UnexpectedException:
            return "unexpected exception";
        case FailureKind::Refused:
            return "refused connection";
        case FailureKind::Dropped:
            return "dropped connection";
    }
    return "unknown";
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
    if (!answer || answer->header.protocol_id != 0 || !protocol::decode_response(answer->pdu).ok())
        return FailureKind::Malformed;
    if ((answer->pdu[0] & protocol::kExceptionBit) != 0 && !exception_expected) {
        return FailureKind::UnexpectedException;
    }
    return FailureKind::WrongAnswer;
}

}  // namespace mblab::load
