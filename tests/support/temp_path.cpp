#include "support/temp_path.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <iostream>
#include <system_error>
#include <vector>

namespace mblab::test {

namespace {

// Removes the paths handed out during a test when it ends; without it every run of the suite
// left several hundred reports and captures in /tmp.
class TempPathSweeper : public ::testing::EmptyTestEventListener {
  public:
    void add(const std::string& path) { paths_.push_back(path); }

    void OnTestEnd(const ::testing::TestInfo& info) override {
        const bool keep = info.result() != nullptr && info.result()->Failed();
        for (const auto& path : paths_) {
            std::error_code ignored;
            if (!keep) {
                std::filesystem::remove_all(path, ignored);
            } else if (std::filesystem::exists(path, ignored)) {
                std::cout << "kept for the failure: " << path << '\n';
            }
        }
        paths_.clear();
    }

  private:
    std::vector<std::string> paths_;
};

TempPathSweeper& sweeper() {
    // gtest owns and deletes appended listeners.
    static TempPathSweeper* const instance = [] {
        auto* created = new TempPathSweeper;
        ::testing::UnitTest::GetInstance()->listeners().Append(created);
        return created;
    }();
    return *instance;
}

}  // namespace

std::string temp_path(const std::string& name) {
    std::string prefix = "mblab-" + std::to_string(::getpid());
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    if (info != nullptr) {
        prefix += std::string("-") + info->test_suite_name() + "." + info->name();
    }
    for (char& c : prefix) {
        if (c == '/') {
            c = '_';
        }
    }
    std::string path = ::testing::TempDir() + prefix + "-" + name;
    if (info != nullptr) {
        sweeper().add(path);
    }
    return path;
}

}  // namespace mblab::test
