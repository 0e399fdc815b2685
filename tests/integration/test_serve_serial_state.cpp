// `mblab serve --listen rtu://... --state FILE`: a device on a serial line keeps acknowledged
// writes across a SIGTERM restart, as on TCP.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "serial_test_support.hpp"
#include "serve_process.hpp"
#include "support/temp_path.hpp"
#include "test_client_support.hpp"

namespace mblab::test {
namespace {

using ::testing::HasSubstr;

namespace fs = std::filesystem;

// `mblab serve` on the line's server end, keeping its state in `state` (saved only on exit).
Serve serve_on_line(const PtyPair& pty, const std::string& state) {
    return Serve({"--listen", "rtu://" + pty.server_end() + "?data=8", "--state", state,
                  "--save-interval", "0"});
}

TEST(ServeSerialState, KeepsAcknowledgedWritesAcrossARestart) {
    PtyPair pty;
    ASSERT_TRUE(pty.ok()) << pty.error();
    const std::string state = temp_path("line.json");
    fs::remove(state);
    const std::string url = "rtu://" + pty.client_end() + "?data=8";
    {
        Serve serve = serve_on_line(pty, state);
        ASSERT_NE(serve.line().find("mblab serve: reference profile on rtu://"), std::string::npos)
            << serve.line();
        auto wrote = run_mblab({"write", url, "register", "0x20", "0xBEEF", "--timeout", "3000"});
        EXPECT_EQ(wrote.status, 0) << wrote.err;
        EXPECT_EQ(serve.terminate(), 0);
    }
    ASSERT_TRUE(fs::exists(state));
    Serve again = serve_on_line(pty, state);
    auto read = run_mblab({"read", url, "holding", "0x20", "--type", "hex", "--timeout", "3000"});
    EXPECT_EQ(read.status, 0) << read.err;
    EXPECT_THAT(read.out, HasSubstr("0xBEEF"));
    EXPECT_EQ(again.terminate(), 0);
}

}  // namespace
}  // namespace mblab::test
