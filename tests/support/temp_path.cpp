#include "support/temp_path.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

namespace mblab::test {

std::string temp_path(const std::string& name) {
    std::string prefix = "mblab-" + std::to_string(::getpid());
    if (const auto* info = ::testing::UnitTest::GetInstance()->current_test_info()) {
        prefix += std::string("-") + info->test_suite_name() + "." + info->name();
    }
    for (char& c : prefix) {
        if (c == '/') {
            c = '_';
        }
    }
    return ::testing::TempDir() + prefix + "-" + name;
}

}  // namespace mblab::test
