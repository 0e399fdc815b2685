#include "shipped/data_dir.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <string>

#include "shipped/build_paths.hpp"
#include "shipped/embedded_files.hpp"

namespace mblab::shipped {
namespace {

namespace fs = std::filesystem;

fs::path running_binary() {
    std::error_code ignored;
    return fs::read_symlink("/proc/self/exe", ignored);
}

bool is_inside(const fs::path& path, const fs::path& directory) {
    std::error_code ignored;
    const auto dir = fs::weakly_canonical(directory, ignored);
    const auto file = fs::weakly_canonical(path, ignored);
    if (dir.empty() || file.empty()) return false;
    return std::mismatch(dir.begin(), dir.end(), file.begin(), file.end()).first == dir.end();
}

// Written at most once per process; the directory is mkdtemp's (mode 0700), so no other user can
// plant or edit what the binary then reads.
fs::path* embedded_root = nullptr;

void remove_embedded_root() {
    std::error_code ignored;
    if (embedded_root) fs::remove_all(*embedded_root, ignored);
}

fs::path write_embedded() {
    const char* tmp = std::getenv("TMPDIR");
    std::string pattern = std::string(tmp && *tmp ? tmp : "/tmp") + "/mblab-data-XXXXXX";
    if (::mkdtemp(pattern.data()) == nullptr) {
        throw std::runtime_error(
            "cannot create a directory for the built-in catalogue and "
            "profiles in " +
            fs::path(pattern).parent_path().string() + "; set TMPDIR or MBLAB_DATA_DIR");
    }
    embedded_root = new fs::path(pattern);
    std::atexit(remove_embedded_root);
    for (const auto& file : embedded_files()) {
        const auto path = *embedded_root / file.name;
        fs::create_directories(path.parent_path());
        std::ofstream out(path, std::ios::binary);
        out.write(file.text.data(), static_cast<std::streamsize>(file.text.size()));
        if (!out) throw std::runtime_error("cannot write " + path.string() + "; set TMPDIR");
    }
    return *embedded_root;
}

}  // namespace

fs::path data_dir(const char* env_var, const char* name) {
    if (const char* dir = std::getenv(env_var); dir && *dir) return dir;
    if (const char* dir = std::getenv("MBLAB_DATA_DIR"); dir && *dir) return fs::path(dir) / name;
    std::error_code ignored;
    const auto binary = running_binary();
    // The source tree only for the binaries of its own build tree: an installed or copied binary
    // must not read a checkout that happens to sit at the path it was built from.
    if (!binary.empty() && is_inside(binary, kBuildDir)) {
        const auto source = fs::path(kSourceDir) / name;
        if (fs::is_directory(source, ignored)) return source;
    }
    // Relative to the binary first, so a package installed under another prefix than the build
    // was configured with (CPack's /usr) finds its own data.
    if (!binary.empty()) {
        const auto beside = binary.parent_path().parent_path() / "share" / "mblab" / name;
        if (fs::is_directory(beside, ignored)) return beside;
    }
    const auto installed = fs::path(kInstalledDataDir) / name;
    if (fs::is_directory(installed, ignored)) return installed;
    static const fs::path embedded = write_embedded();
    return embedded / name;
}

}  // namespace mblab::shipped
