#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "protocol/result.hpp"

// Byte patterns as conformance labs write them: "00 00 00 00 00 04 {unit} 01 01 XX".
//   hex bytes     literal bytes ("00", or several at once: "0010")
//   XX            any one byte
//   FF*246, XX*8  one byte (or any byte) repeated
//   {len}         the two-byte MBAP length: the count of bytes that follow it
//   {name}        a fact about the device under test ({unit}, {read_only_register}, ...)
//   ...           any number of further bytes (last token only)
namespace mblab::conformance {

struct PatternToken {
    enum class Kind : std::uint8_t { Byte, Any, Length, Fact, Rest };
    Kind kind = Kind::Byte;
    std::uint8_t value = 0;  // Byte
    std::string name;        // Fact
};

struct PatternError {
    std::size_t column = 0;  // 1-based position of the bad token in the text
    std::string reason;
};

class Pattern {
  public:
    static protocol::Result<Pattern, PatternError> parse(std::string_view text);

    // Builders for procedures that compute what they expect.
    Pattern& byte(std::uint8_t value);
    Pattern& u16(std::uint16_t value);
    Pattern& any(std::size_t count = 1);
    Pattern& length();
    Pattern& fact(std::string name);

    const std::vector<PatternToken>& tokens() const { return tokens_; }
    // Names of the facts used, in order of first use.
    std::vector<std::string> facts() const;
    // True when the pattern is fixed bytes once facts are put in (no XX, no ...).
    bool is_concrete() const;

  private:
    std::vector<PatternToken> tokens_;
};

// Looks up a fact's bytes; nullopt when the device under test does not declare it.
class FactSource {
  public:
    virtual ~FactSource() = default;
    virtual std::optional<std::vector<std::uint8_t>> fact(std::string_view name) const = 0;
};

// A pattern with its facts put in: only Byte, Any, Length and Rest tokens remain.
struct ResolvedPattern {
    std::vector<PatternToken> tokens;
};

struct MissingFact {
    std::string name;
};

protocol::Result<ResolvedPattern, MissingFact> resolve(const Pattern& pattern,
                                                       const FactSource& facts);

// The bytes of a concrete pattern, {len} computed. Any XX or ... is sent as nothing (a caller
// checks is_concrete() first; the catalogue loader refuses requests that are not).
std::vector<std::uint8_t> render_bytes(const ResolvedPattern& pattern);

struct MatchResult {
    bool matched = false;
    // Byte positions (in the received frame's numbering) that differ from the pattern. A position
    // past the end of the received bytes means a byte is missing; past the pattern's end, extra.
    std::vector<std::size_t> differs;
    // The expected bytes laid over the received ones, one entry per position: "00", "XX",
    // or for {len} the value it should have had; used to print the expected line.
    std::vector<std::string> expected_cells;
};

MatchResult match(const ResolvedPattern& pattern, std::span<const std::uint8_t> received);

// "00 00 00 00 00 04 01 01 01 XX" as the user wrote it, facts put in.
std::string to_text(const ResolvedPattern& pattern);

}  // namespace mblab::conformance
