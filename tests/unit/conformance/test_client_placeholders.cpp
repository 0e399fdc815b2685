#include <gtest/gtest.h>

#include "conformance/client_process.hpp"

namespace mblab::conformance {
namespace {

TEST(ClientPlaceholders, EachNameIsFilledEverywhereItStands) {
    const ClientPlaceholders values{"127.0.0.1", "1502", "tcp://127.0.0.1:1502", "7", "100", "2"};
    EXPECT_EQ(
        fill_placeholders("{host}:{port} {url} -a {unit} -r {address} -c {count} {host}", values),
        "127.0.0.1:1502 tcp://127.0.0.1:1502 -a 7 -r 100 -c 2 127.0.0.1");
    // Not on a line: {device} and {baud} are empty, unknown names stay as written.
    EXPECT_EQ(fill_placeholders("[{device}][{baud}] {other}", values), "[][] {other}");
}

// A client that takes a line apart (mbpoll -m rtu -b BAUD DEVICE) gets the pty's path and speed.
TEST(ClientPlaceholders, ALineGivesItsDeviceAndBaud) {
    ClientPlaceholders values{"",  "",    "rtu:///dev/pts/4?baud=9600&parity=E&stop=1&data=8",
                              "1", "100", "2"};
    values.device = "/dev/pts/4";
    values.baud = "9600";
    EXPECT_EQ(fill_placeholders("mbpoll -m rtu -b {baud} {device}", values),
              "mbpoll -m rtu -b 9600 /dev/pts/4");
    // A value holding a placeholder's name is not filled again.
    values.device = "{baud}";
    EXPECT_EQ(fill_placeholders("{device}", values), "{baud}");
}

}  // namespace
}  // namespace mblab::conformance
