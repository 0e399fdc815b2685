#pragma once

#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace mblab::cli {

// The report files of a run, checked before any traffic: a run of an hour must not end with
// "cannot write". Each is opened for writing, created when missing but never truncated, so a
// report from an earlier run stays whole until the new one replaces it. A file the check created
// is removed again unless the run writes it, so a refused or failed run leaves no empty report.
// Shared by conform and load.
class ReportFiles {
  public:
    ReportFiles() = default;
    ReportFiles(const ReportFiles&) = delete;
    ReportFiles& operator=(const ReportFiles&) = delete;
    ~ReportFiles();

    // False with `error` naming the option and the path when `path` cannot be written.
    bool check(std::string_view option, const std::string& path, std::string& error);

    // The run wrote `path`: it stays.
    void written(const std::string& path) { std::erase(created_, path); }

  private:
    std::vector<std::string> created_;
    std::vector<std::pair<std::string, std::string>> checked_;  // option, absolute path
};

}  // namespace mblab::cli
