#pragma once

#include <unistd.h>

#include <filesystem>
#include <string>

#include "security/pki.hpp"

// A lab PKI as `mblab pki` writes it, made once for a test suite in a directory of its own and
// removed with it: tests that need certificates share one instead of each making its own.
namespace mblab::test {

class LabPki {
  public:
    // Makes the PKI under the system's temporary directory; `made` says whether it worked, and
    // `error` why not.
    explicit LabPki(const std::string& name)
        : dir_(std::filesystem::temp_directory_path() /
               ("mblab-" + name + "-" + std::to_string(::getpid()))) {
        std::filesystem::remove_all(dir_);
        auto made = security::make_lab_pki(dir_, {});
        if (!made) error_ = made.error();
    }
    ~LabPki() {
        std::error_code ignored;
        std::filesystem::remove_all(dir_, ignored);
    }
    LabPki(const LabPki&) = delete;
    LabPki& operator=(const LabPki&) = delete;

    bool made() const { return error_.empty(); }
    const std::string& error() const { return error_; }
    const std::filesystem::path& dir() const { return dir_; }
    // A file of the PKI: "ca.pem", "client-Operator.key", ...
    std::string file(const std::string& name) const { return (dir_ / name).string(); }

  private:
    std::filesystem::path dir_;
    std::string error_;
};

}  // namespace mblab::test
