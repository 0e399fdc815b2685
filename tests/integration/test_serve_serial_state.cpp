// `mblab serve --listen rtu://... --state FILE`: a device on a serial line keeps acknowledged
// writes across a SIGTERM restart, as on TCP.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>

#include <filesystem>
#include <string>

#include "child_process.hpp"
#include "serial_test_support.hpp"
#include "support/temp_path.hpp"
#include "test_client_support.hpp"

namespace mblab::test {
namespace {

using ::testing::HasSubstr;

namespace fs = std::filesystem;

// `mblab serve` on the line's server end until stop() (SIGTERM).
class ServeOnLine {
  public:
    ServeOnLine(const PtyPair& pty, const std::string& state)
        : child_({MBLAB_BINARY, "serve", "--listen", "rtu://" + pty.server_end() + "?data=8",
                  "--state", state, "--save-interval", "0"}) {
        line_ = child_.read_stdout_line(std::chrono::seconds(10)).value_or("");
    }
    const std::string& line() const { return line_; }
    std::optional<int> stop() {
        child_.signal(SIGTERM);
        return child_.wait_exit(std::chrono::seconds(10));
    }

  private:
    ChildProcess child_;
    std::string line_;
};

TEST(ServeSerialState, KeepsAcknowledgedWritesAcrossARestart) {
    PtyPair pty;
    ASSERT_TRUE(pty.ok()) << pty.error();
    const std::string state = temp_path("line.json");
    fs::remove(state);
    const std::string url = "rtu://" + pty.client_end() + "?data=8";
    {
        ServeOnLine serve(pty, state);
        ASSERT_NE(serve.line().find("mblab serve: reference profile on rtu://"), std::string::npos)
            << serve.line();
        auto wrote = run_mblab({"write", url, "register", "0x20", "0xBEEF", "--timeout", "3000"});
        EXPECT_EQ(wrote.status, 0) << wrote.err;
        EXPECT_EQ(serve.stop(), 0);
    }
    ASSERT_TRUE(fs::exists(state));
    ServeOnLine again(pty, state);
    auto read = run_mblab({"read", url, "holding", "0x20", "--type", "hex", "--timeout", "3000"});
    EXPECT_EQ(read.status, 0) << read.err;
    EXPECT_THAT(read.out, HasSubstr("0xBEEF"));
    EXPECT_EQ(again.stop(), 0);
}

}  // namespace
}  // namespace mblab::test
