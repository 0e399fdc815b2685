#include "security/role_text.hpp"

#include <array>
#include <cstddef>

namespace mblab::security {

const char* role_text_problem(std::string_view text) {
    if (text.empty()) return "is empty";
    std::size_t i = 0;
    while (i < text.size()) {
        const auto lead = static_cast<unsigned char>(text[i]);
        if (lead < 0x80) {
            if (lead < 0x20 || lead == 0x7F) return "contains a control character";
            ++i;
            continue;
        }
        std::size_t extra = 0;
        unsigned int code = 0;
        if (lead >= 0xC2 && lead <= 0xDF) {
            extra = 1;
            code = lead & 0x1FU;
        } else if (lead >= 0xE0 && lead <= 0xEF) {
            extra = 2;
            code = lead & 0x0FU;
        } else if (lead >= 0xF0 && lead <= 0xF4) {
            extra = 3;
            code = lead & 0x07U;
        } else {
            return "is not valid UTF-8";
        }
        if (text.size() - i <= extra) return "is not valid UTF-8";
        for (std::size_t k = 1; k <= extra; ++k) {
            const auto next = static_cast<unsigned char>(text[i + k]);
            if ((next & 0xC0U) != 0x80U) return "is not valid UTF-8";
            code = (code << 6U) | (next & 0x3FU);
        }
        // Overlong forms, UTF-16 surrogates and values past U+10FFFF are not UTF-8 either.
        static constexpr std::array<unsigned int, 4> kLeast = {0, 0x80, 0x800, 0x10000};
        if (code < kLeast[extra] || (code >= 0xD800 && code <= 0xDFFF) || code > 0x10FFFF) {
            return "is not valid UTF-8";
        }
        if (code <= 0x9F) return "contains a control character";
        i += extra + 1;
    }
    return nullptr;
}

}  // namespace mblab::security
