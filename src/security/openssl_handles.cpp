#include "security/openssl_handles.hpp"

#include <openssl/err.h>

#include <array>

namespace mblab::security {

std::string openssl_error(const std::string& what) {
    const unsigned long code = ERR_get_error();
    ERR_clear_error();
    if (code == 0) return what;
    // 256 bytes is what ERR_error_string_n's documentation asks for; a longer reason is cut.
    std::array<char, 256> text{};
    ERR_error_string_n(code, text.data(), text.size());
    return what + ": " + text.data();
}

}  // namespace mblab::security
