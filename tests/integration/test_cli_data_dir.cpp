// The shipped catalogue and profiles are compiled into the binary: a copy of it run away from its
// source and build trees still lists and runs the suites; MBLAB_DATA_DIR overrides them.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>
#include <fstream>

#include "test_client_support.hpp"

namespace mblab::test {
namespace {

using ::testing::HasSubstr;

namespace fs = std::filesystem;

class CopiedBinary : public ::testing::Test {
  protected:
    void SetUp() override {
        std::string pattern = (fs::temp_directory_path() / "mblab-copy-XXXXXX").string();
        ASSERT_NE(::mkdtemp(pattern.data()), nullptr);
        dir_ = pattern;
        fs::copy_file(MBLAB_BINARY, dir_ / "mblab");
    }
    void TearDown() override {
        std::error_code ignored;
        fs::remove_all(dir_, ignored);
    }
    // Runs the copy with its own directory as the working directory and no data directory
    // variables but those in `env` ("NAME=value ...").
    Ran run(const std::string& args, const std::string& env = "") const {
        const std::string script = "cd '" + dir_.string() +
                                   "' && exec env -u MBLAB_DATA_DIR -u MBLAB_CATALOGUE_DIR "
                                   "-u MBLAB_PROFILES_DIR " +
                                   env + " ./mblab " + args;
        return run_program({"/bin/sh", "-c", script}, std::chrono::seconds(60));
    }
    fs::path dir_;
};

TEST_F(CopiedBinary, ListsTheBuiltInSuites) {
    auto ran = run("conform --list");
    EXPECT_EQ(ran.status, 0) << ran.err;
    for (const char* suite : {"policy-2.1 (", "device-id (", "diagnostics (", "exceptions (",
                              "function-codes (", "mbap (", "serial ("}) {
        EXPECT_NE(("\n" + ran.out).find(std::string("\n") + suite), std::string::npos)
            << suite << " missing from:\n"
            << ran.out;
    }
    EXPECT_EQ(ran.out.find(MBLAB_SOURCE_DIR), std::string::npos) << ran.out;
}

TEST_F(CopiedBinary, PassesThePolicyAgainstItsBuiltInDevice) {
    auto ran = run("conform --suite policy-2.1");
    EXPECT_EQ(ran.status, 0) << ran.out << ran.err;
    EXPECT_THAT(ran.out, HasSubstr("Summary: 18 passed, 0 failed"));
    EXPECT_EQ(ran.out.find(MBLAB_SOURCE_DIR), std::string::npos) << ran.out;
}

TEST_F(CopiedBinary, ReadsAnEditedCopyFromMblabDataDir) {
    fs::create_directories(dir_ / "data" / "catalogue");
    fs::copy(fs::path(MBLAB_SOURCE_DIR) / "profiles", dir_ / "data" / "profiles");
    std::ofstream(dir_ / "data" / "catalogue" / "mine.toml") << R"([suite]
name = "mine"
title = "An edited catalogue"
source = "test"

[[case]]
id = "1"
title = "Read one register"
source = "test"
request = "00 00 00 00 00 06 01 03 00 00 00 01"
expect = "00 00 00 00 00 05 01 03 02 XX XX"
)";
    auto ran = run("conform --list", "MBLAB_DATA_DIR=data");
    EXPECT_EQ(ran.status, 0) << ran.err;
    EXPECT_EQ(ran.out.rfind("mine (data/catalogue/mine.toml): An edited catalogue\n", 0), 0u)
        << ran.out;
    EXPECT_EQ(ran.out.find("policy-2.1"), std::string::npos) << ran.out;
}

}  // namespace
}  // namespace mblab::test
