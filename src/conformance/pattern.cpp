#include "conformance/pattern.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cctype>

namespace mblab::conformance {

namespace {

int hex_digit(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}

bool is_fact_name(std::string_view name) {
    if (name.empty()) return false;
    return std::all_of(name.begin(), name.end(), [](char c) {
        return std::islower(static_cast<unsigned char>(c)) ||
               std::isdigit(static_cast<unsigned char>(c)) || c == '_';
    });
}

std::string cell(std::uint8_t value) {
    return fmt::format("{:02X}", value);
}

}  // namespace

protocol::Result<Pattern, PatternError> Pattern::parse(std::string_view text) {
    Pattern out;
    std::size_t i = 0;
    while (i < text.size()) {
        if (std::isspace(static_cast<unsigned char>(text[i]))) {
            ++i;
            continue;
        }
        std::size_t start = i;
        while (i < text.size() && !std::isspace(static_cast<unsigned char>(text[i])))
            ++i;
        std::string_view token = text.substr(start, i - start);
        auto fail = [&](std::string reason) {
            return PatternError{start + 1, fmt::format("'{}': {}", token, reason)};
        };
        if (!out.tokens_.empty() && out.tokens_.back().kind == PatternToken::Kind::Rest) {
            return fail("nothing may follow '...'");
        }
        std::size_t repeat = 1;
        if (auto star = token.find('*'); star != std::string_view::npos) {
            auto count = token.substr(star + 1);
            token = token.substr(0, star);
            repeat = 0;
            for (char c : count) {
                if (!std::isdigit(static_cast<unsigned char>(c)) || repeat > 1000) {
                    repeat = 0;
                    break;
                }
                repeat = repeat * 10 + static_cast<std::size_t>(c - '0');
            }
            if (repeat == 0 || repeat > 260 || token.size() != 2 || token == "..") {
                return fail("a repeat is one byte or XX, '*', and a count from 1 to 260");
            }
        }
        if (token == "XX" || token == "xx") {
            out.any(repeat);
        } else if (repeat > 1) {
            int high = hex_digit(token[0]);
            int low = hex_digit(token[1]);
            if (high < 0 || low < 0) return fail("a repeat is one byte or XX, '*', and a count");
            for (std::size_t k = 0; k < repeat; ++k)
                out.byte(static_cast<std::uint8_t>(high << 4 | low));
        } else if (token == "...") {
            out.tokens_.push_back({PatternToken::Kind::Rest, 0, {}});
        } else if (token.front() == '{') {
            if (token.back() != '}') return fail("a placeholder ends with '}'");
            std::string_view name = token.substr(1, token.size() - 2);
            if (!is_fact_name(name)) {
                return fail("a placeholder name is lower-case letters, digits and '_'");
            }
            if (name == "len") {
                out.length();
            } else {
                out.fact(std::string(name));
            }
        } else {
            if (token.size() % 2 != 0) return fail("hex bytes are written as pairs of digits");
            for (std::size_t k = 0; k < token.size(); k += 2) {
                int high = hex_digit(token[k]);
                int low = hex_digit(token[k + 1]);
                if (high < 0 || low < 0) {
                    return fail("expected hex bytes, XX, {placeholder} or ...");
                }
                out.byte(static_cast<std::uint8_t>(high << 4 | low));
            }
        }
    }
    if (out.tokens_.empty()) return PatternError{1, "the pattern is empty"};
    return out;
}

Pattern& Pattern::byte(std::uint8_t value) {
    tokens_.push_back({PatternToken::Kind::Byte, value, {}});
    return *this;
}

Pattern& Pattern::u16(std::uint16_t value) {
    byte(static_cast<std::uint8_t>(value >> 8));
    return byte(static_cast<std::uint8_t>(value & 0xFF));
}

Pattern& Pattern::any(std::size_t count) {
    for (std::size_t i = 0; i < count; ++i)
        tokens_.push_back({PatternToken::Kind::Any, 0, {}});
    return *this;
}

Pattern& Pattern::length() {
    tokens_.push_back({PatternToken::Kind::Length, 0, {}});
    return *this;
}

Pattern& Pattern::fact(std::string name) {
    tokens_.push_back({PatternToken::Kind::Fact, 0, std::move(name)});
    return *this;
}

std::vector<std::string> Pattern::facts() const {
    std::vector<std::string> names;
    for (const auto& token : tokens_) {
        if (token.kind == PatternToken::Kind::Fact &&
            std::find(names.begin(), names.end(), token.name) == names.end()) {
            names.push_back(token.name);
        }
    }
    return names;
}

bool Pattern::is_concrete() const {
    return std::none_of(tokens_.begin(), tokens_.end(), [](const PatternToken& token) {
        return token.kind == PatternToken::Kind::Any || token.kind == PatternToken::Kind::Rest;
    });
}

protocol::Result<ResolvedPattern, MissingFact> resolve(const Pattern& pattern,
                                                       const FactSource& facts) {
    ResolvedPattern out;
    for (const auto& token : pattern.tokens()) {
        if (token.kind != PatternToken::Kind::Fact) {
            out.tokens.push_back(token);
            continue;
        }
        auto bytes = facts.fact(token.name);
        if (!bytes) return MissingFact{token.name};
        for (std::uint8_t value : *bytes) {
            out.tokens.push_back({PatternToken::Kind::Byte, value, {}});
        }
    }
    return out;
}

namespace {

// Bytes the pattern describes after position `index`, or nullopt when it ends in "...".
std::optional<std::size_t> fixed_size_after(const ResolvedPattern& pattern, std::size_t index) {
    std::size_t size = 0;
    for (std::size_t i = index + 1; i < pattern.tokens.size(); ++i) {
        switch (pattern.tokens[i].kind) {
            case PatternToken::Kind::Rest:
                return std::nullopt;
            case PatternToken::Kind::Length:
                size += 2;
                break;
            default:
                size += 1;
                break;
        }
    }
    return size;
}

}  // namespace

std::vector<std::uint8_t> render_bytes(const ResolvedPattern& pattern) {
    std::vector<std::uint8_t> out;
    for (std::size_t i = 0; i < pattern.tokens.size(); ++i) {
        const auto& token = pattern.tokens[i];
        if (token.kind == PatternToken::Kind::Byte) {
            out.push_back(token.value);
        } else if (token.kind == PatternToken::Kind::Length) {
            auto length = fixed_size_after(pattern, i).value_or(0);
            out.push_back(static_cast<std::uint8_t>(length >> 8));
            out.push_back(static_cast<std::uint8_t>(length & 0xFF));
        }
    }
    return out;
}

MatchResult match(const ResolvedPattern& pattern, std::span<const std::uint8_t> received) {
    MatchResult out;
    std::size_t pos = 0;
    bool open_ended = false;
    auto expect_byte = [&](std::optional<std::uint8_t> value, std::string text) {
        if (pos >= received.size() || (value && received[pos] != *value)) {
            out.differs.push_back(pos);
        }
        out.expected_cells.push_back(std::move(text));
        ++pos;
    };
    for (std::size_t i = 0; i < pattern.tokens.size(); ++i) {
        const auto& token = pattern.tokens[i];
        switch (token.kind) {
            case PatternToken::Kind::Byte:
                expect_byte(token.value, cell(token.value));
                break;
            case PatternToken::Kind::Any:
                expect_byte(std::nullopt, "XX");
                break;
            case PatternToken::Kind::Length: {
                // With a fixed-size pattern the length is known; after "..." it must agree with
                // the bytes that really came.
                std::size_t after =
                    fixed_size_after(pattern, i)
                        .value_or(received.size() > pos + 2 ? received.size() - pos - 2 : 0);
                auto high = static_cast<std::uint8_t>((after >> 8) & 0xFF);
                auto low = static_cast<std::uint8_t>(after & 0xFF);
                expect_byte(high, cell(high));
                expect_byte(low, cell(low));
                break;
            }
            case PatternToken::Kind::Rest:
                open_ended = true;
                out.expected_cells.emplace_back("...");
                break;
            case PatternToken::Kind::Fact:
                break;  // resolved away before matching
        }
    }
    if (!open_ended) {
        for (; pos < received.size(); ++pos)
            out.differs.push_back(pos);
    }
    out.matched = out.differs.empty();
    return out;
}

std::string to_text(const ResolvedPattern& pattern) {
    std::string out;
    for (const auto& token : pattern.tokens) {
        if (!out.empty()) out += ' ';
        switch (token.kind) {
            case PatternToken::Kind::Byte:
                out += cell(token.value);
                break;
            case PatternToken::Kind::Any:
                out += "XX";
                break;
            case PatternToken::Kind::Length:
                out += "{len}";
                break;
            case PatternToken::Kind::Rest:
                out += "...";
                break;
            case PatternToken::Kind::Fact:
                out += "{" + token.name + "}";
                break;
        }
    }
    return out;
}

}  // namespace mblab::conformance
