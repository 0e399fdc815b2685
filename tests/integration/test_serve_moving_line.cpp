// `mblab serve moving --listen rtu://...`: the behaviours' timer runs on a serial line's server as
// on TCP. The test polls until the sine at holding register 1 changes (at most 20 s); it never
// times the server.
#include <gtest/gtest.h>
#include <signal.h>

#include <string>
#include <thread>

#include "child_process.hpp"
#include "serial_test_support.hpp"
#include "test_client_support.hpp"

namespace mblab::test {
namespace {

using namespace std::chrono_literals;

TEST(ServeMovingLine, SineMovesWhenReadOverRtu) {
    PtyPair pty;
    ASSERT_TRUE(pty.ok()) << pty.error();
    ChildProcess serve(
        {MBLAB_BINARY, "serve", "moving", "--listen", "rtu://" + pty.server_end() + "?data=8"});
    const auto line = serve.read_stdout_line(10s).value_or("");
    ASSERT_NE(line.find("mblab serve: moving profile on rtu://"), std::string::npos) << line;
    const std::string url = "rtu://" + pty.client_end() + "?data=8";
    const auto read = [&] { return run_mblab({"read", url, "holding", "1", "--timeout", "3000"}); };
    const auto first = read();
    ASSERT_EQ(first.status, 0) << first.err;
    auto later = first;
    for (int i = 0; i < 100 && later.out == first.out; ++i) {
        std::this_thread::sleep_for(200ms);
        later = read();
        ASSERT_EQ(later.status, 0) << later.err;
    }
    EXPECT_NE(later.out, first.out);
    serve.signal(SIGTERM);
    EXPECT_EQ(serve.wait_exit(10s), 0);
}

}  // namespace
}  // namespace mblab::test
