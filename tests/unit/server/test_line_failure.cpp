#include <gtest/gtest.h>

#include <asio/error.hpp>
#include <system_error>

#include "server/serial_session.hpp"

namespace mblab::server {
namespace {

// Issue 17 item 11: a pty's hang-up showed as "Input/output error" when the kernel reported EIO
// before the end of file, and SerialPort.ReportsALineThatHangsUp failed now and then.
TEST(LineFailure, EndOfFileAndEioAreBothAHangUp) {
    EXPECT_EQ(line_failure_text(asio::error::eof), "the line hung up");
    EXPECT_EQ(line_failure_text(std::make_error_code(std::errc::io_error)), "the line hung up");
}

TEST(LineFailure, OtherErrorsSayWhatTheyAre) {
    EXPECT_EQ(line_failure_text(std::make_error_code(std::errc::permission_denied)),
              "Permission denied");
}

}  // namespace
}  // namespace mblab::server
