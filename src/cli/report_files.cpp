#include "cli/report_files.hpp"

#include <fcntl.h>
#include <fmt/core.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "conformance/reports.hpp"

namespace mblab::cli {

namespace {

std::string identity(const std::string& path) {
    std::error_code ignored;
    return std::filesystem::absolute(path, ignored).lexically_normal().string();
}

std::string why_not(const std::string& path, int error) {
    const std::string directory = std::filesystem::path(path).parent_path().string();
    const std::string parent = directory.empty() ? std::string(".") : directory;
    switch (error) {
        case ENOENT:
            return fmt::format("directory {} does not exist", parent);
        case ENOTDIR:
            return fmt::format("{} is not a directory", parent);
        case EISDIR:
            return "it is a directory";
        case EACCES:
        case EPERM:
            return "permission denied";
        case EROFS:
            return "read-only file system";
        default: {
            std::string text = std::strerror(error);
            if (!text.empty()) text[0] = static_cast<char>(std::tolower(text[0]));
            return text;
        }
    }
}

}  // namespace

bool ReportFiles::check(std::string_view option, const std::string& path, std::string& error) {
    if (path.empty()) return true;
    if (path == kStandardOutput) {
        if (!standard_output_.empty()) {
            error = "only one report can go to standard output (-)";
            return false;
        }
        standard_output_ = option;
        return true;
    }
    const auto same = std::find_if(checked_.begin(), checked_.end(),
                                   [&](const auto& seen) { return seen.second == identity(path); });
    if (same != checked_.end()) {
        error = fmt::format("{} {}: the same file as {}; each report needs its own file", option,
                            path, same->first);
        return false;
    }
    int fd = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
    if (fd < 0 && errno == ENOENT) {
        // Missing: tried as the temporary file the report is written through, then removed.
        const std::string probe = fmt::format("{}.{}.tmp", path, ::getpid());
        fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd >= 0) ::unlink(probe.c_str());
    }
    if (fd < 0) {
        error =
            fmt::format("{} {}: cannot write the report: {}", option, path, why_not(path, errno));
        return false;
    }
    ::close(fd);
    checked_.emplace_back(std::string(option), identity(path));
    return true;
}

bool ReportFiles::write(const std::string& path, const std::string& text, std::string& error) {
    if (path == kStandardOutput) {
        std::fwrite(text.data(), 1, text.size(), stdout);
        std::fflush(stdout);
        return true;
    }
    return conformance::write_text_file(path, text, error);
}

void TextReports::add_to(CLI::App& command, std::string_view junit_case,
                         std::string_view html_page) {
    command.add_option("--json", json,
                       "write the report as JSON to FILE ('-': standard output, the console report "
                       "then going to standard error)");
    command.add_option("--junit", junit,
                       fmt::format("write the report as JUnit XML to FILE ('-': standard output), "
                                   "one test case per {}",
                                   junit_case));
    command.add_option(
        "--html", html,
        fmt::format("write the report as one self-contained HTML page to FILE: {}", html_page));
}

bool TextReports::check(ReportFiles& files, std::string& error) const {
    return files.check("--json", json, error) && files.check("--junit", junit, error) &&
           files.check("--html", html, error);
}

}  // namespace mblab::cli
