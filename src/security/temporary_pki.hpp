#pragma once

#include <filesystem>
#include <string>

// A lab PKI made for one run in a new directory of its own, removed with the object: the
// built-in device's and the client examiner's certificates when no PKI is given.
namespace mblab::security {

class TemporaryPki {
  public:
    TemporaryPki() = default;
    TemporaryPki(const TemporaryPki&) = delete;
    TemporaryPki& operator=(const TemporaryPki&) = delete;
    ~TemporaryPki();

    // Makes the directory (mblab-STEM-XXXXXX under the temporary directory) and the PKI in it;
    // "" when made, else why not.
    std::string make(const std::string& stem);
    const std::filesystem::path& dir() const { return dir_; }
    // NAME in it, as a path string ("ca.pem").
    std::string file(const std::string& name) const { return (dir_ / name).string(); }

  private:
    std::filesystem::path dir_;
};

}  // namespace mblab::security
