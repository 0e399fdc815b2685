#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "conformance/pattern.hpp"

// Judging answers at load-test speed: no allocation, no evidence. The evidence of a failure is
// built afterwards with judge(), from the same patterns.
namespace mblab::load {

// The kinds of failure a load run counts (CTP 8.4: "no detected failures anywhere").
enum class FailureKind : std::uint8_t {
    Timeout,              // no whole answer before --timeout
    Malformed,            // an answer that is not a valid Modbus/TCP response
    WrongAnswer,          // a valid response, but not the one the request calls for
    UnexpectedException,  // an exception where data (or no exception) was expected
    Refused,              // the connection could not be made
    Dropped,              // the device closed or reset the connection
};
inline constexpr std::size_t kFailureKinds = 6;

// "timeout", "malformed", "wrong_answer", "exception", "refused", "dropped": report keys.
std::string_view failure_key(FailureKind kind);
// "timeout", "malformed answer", ...: what users read.
std::string_view failure_label(FailureKind kind);

// An expected answer compiled to its literal bytes and its length field. The transaction id
// (bytes 0 and 1) is not compared: the load runner writes its own ids into the requests and
// matches answers to requests by them.
class AnswerPattern {
  public:
    explicit AnswerPattern(const conformance::ResolvedPattern& pattern);

    bool matches(std::span<const std::uint8_t> frame) const;
    // The function byte the pattern expects has the exception bit set.
    bool expects_exception() const { return expects_exception_; }

  private:
    struct Literal {
        std::uint16_t at = 0;
        std::uint8_t value = 0;
    };
    std::vector<Literal> literals_;
    std::size_t size_ = 0;  // bytes before any "..."
    bool open_ended_ = false;
    std::optional<std::size_t> length_at_;  // where {len} sits
    bool expects_exception_ = false;
};

// Nothing when `frame` (a whole MBAP ADU of at least 8 bytes) matches one of `alternatives`;
// otherwise the kind of failure: malformed when the response does not decode, an unexpected
// exception when none of the alternatives is one, else a wrong answer.
std::optional<FailureKind> judge_answer(std::span<const AnswerPattern> alternatives,
                                        std::span<const std::uint8_t> frame);

}  // namespace mblab::load
