#include "protocol/function_code.hpp"

#include <array>

#include "protocol/function_table.hpp"
#include "support/hex_digits.hpp"
#include "support/name_table.hpp"

namespace mblab::protocol {

namespace {

// "function 0xNN" for every code, built at compile time so naming an unknown code never
// allocates and the returned view stays valid for the life of the program.
struct UnknownFunctionNames {
    static constexpr std::size_t kLength = 13;  // "function 0x41"
    std::array<std::array<char, kLength>, 256> names{};

    constexpr UnknownFunctionNames() {
        constexpr char kPrefix[] = "function 0x";
        for (std::size_t code = 0; code < names.size(); ++code) {
            for (std::size_t i = 0; i + 1 < sizeof kPrefix; ++i)
                names[code][i] = kPrefix[i];
            names[code][kLength - 2] = kHexDigits[code >> 4];
            names[code][kLength - 1] = kHexDigits[code & 0xF];
        }
    }
};

constexpr UnknownFunctionNames kUnknownFunctionNames;

}  // namespace

bool is_public_function(std::uint8_t code) {
    return find_function(code) != nullptr;
}

std::string_view function_name(std::uint8_t code) {
    if (const FunctionRow* row = find_function(code)) return row->name;
    const auto& name = kUnknownFunctionNames.names[code];
    return {name.data(), name.size()};
}

namespace {

struct DiagnosticSubRow {
    DiagnosticSub value;
    std::string_view name;
    bool echoes = false;
};

constexpr DiagnosticSubRow kDiagnosticSubs[] = {
#define MBLAB_DIAGNOSTIC_ROW(enumerator, code, name, echoes) \
    {DiagnosticSub::enumerator, name, echoes},
    MBLAB_DIAGNOSTIC_SUBS(MBLAB_DIAGNOSTIC_ROW)
#undef MBLAB_DIAGNOSTIC_ROW
};

}  // namespace

bool is_known_diagnostic_sub(std::uint16_t sub) {
    return row_of(kDiagnosticSubs, static_cast<DiagnosticSub>(sub)) != nullptr;
}

std::string_view diagnostic_sub_name(std::uint16_t sub) {
    return word_of(kDiagnosticSubs, static_cast<DiagnosticSub>(sub), &DiagnosticSubRow::name,
                   "reserved sub-function");
}

bool diagnostic_answer_echoes(std::uint16_t sub) {
    return word_of(kDiagnosticSubs, static_cast<DiagnosticSub>(sub), &DiagnosticSubRow::echoes,
                   false);
}

}  // namespace mblab::protocol
