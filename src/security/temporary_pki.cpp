#include "security/temporary_pki.hpp"

#include <stdlib.h>

#include <cerrno>
#include <cstring>

#include "security/pki.hpp"

namespace mblab::security {

TemporaryPki::~TemporaryPki() {
    if (dir_.empty()) return;
    std::error_code ignored;
    std::filesystem::remove_all(dir_, ignored);
}

std::string TemporaryPki::make(const std::string& stem) {
    std::string pattern =
        (std::filesystem::temp_directory_path() / ("mblab-" + stem + "-XXXXXX")).string();
    if (::mkdtemp(pattern.data()) == nullptr) {
        return std::string("cannot make a directory for the lab PKI: ") + std::strerror(errno);
    }
    dir_ = pattern;
    PkiRequest request;
    request.overwrite = true;  // the directory is new, and mkdtemp made it
    if (auto made = make_lab_pki(dir_, request); !made) return made.error();
    return "";
}

}  // namespace mblab::security
