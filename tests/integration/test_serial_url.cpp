// Serial link addresses: what they set, and the one-line errors a user sees for a typo; the
// silent intervals derived from the baud rate; opening a port that is not there.
#include <gtest/gtest.h>

#include <asio/io_context.hpp>
#include <future>
#include <memory>
#include <string>

#include "device/profile_paths.hpp"
#include "serial_test_support.hpp"
#include "server/serial_server.hpp"
#include "transport/serial_port.hpp"
#include "transport/serial_url.hpp"

namespace mblab::test {
namespace {

using transport::Parity;
using transport::SerialUrl;

std::string error_of(std::string_view url) {
    auto parsed = transport::parse_serial_url(url);
    return parsed ? "(parsed)" : parsed.error();
}

TEST(SerialUrl, ReadsEverySettingOfAnRtuLine) {
    auto url = transport::parse_serial_url(
        "rtu:///dev/ttyUSB0?baud=9600&parity=O&stop=2&data=8&strict=1&timeout=250&units=1-3,7");
    ASSERT_TRUE(url) << url.error();
    EXPECT_EQ(url->kind, SerialUrl::Kind::Rtu);
    EXPECT_EQ(url->line.device, "/dev/ttyUSB0");
    EXPECT_EQ(url->line.baud, 9600u);
    EXPECT_EQ(url->line.parity, Parity::Odd);
    EXPECT_EQ(url->line.stop_bits, 2);
    EXPECT_EQ(url->line.data_bits, 8);
    EXPECT_TRUE(url->strict_timing);
    EXPECT_EQ(url->response_timeout.count(), 250);
    EXPECT_EQ(url->units.count(), 4u);
    EXPECT_TRUE(url->units.test(1) && url->units.test(3) && url->units.test(7));
    EXPECT_EQ(transport::format_serial_url(*url),
              "rtu:///dev/ttyUSB0?baud=9600&parity=O&stop=2&data=8&strict=1");
}

TEST(SerialUrl, DefaultsFollowTheSerialLineSpec) {
    auto rtu = transport::parse_serial_url("rtu:///dev/ttyS0");
    ASSERT_TRUE(rtu);
    EXPECT_EQ(transport::format_serial_url(*rtu),
              "rtu:///dev/ttyS0?baud=19200&parity=E&stop=1&data=8");
    EXPECT_EQ(rtu->units.count(), 247u);
    EXPECT_FALSE(rtu->units.test(0));
    EXPECT_EQ(rtu->response_timeout.count(), 1000);
    EXPECT_FALSE(rtu->strict_timing);
    auto ascii = transport::parse_serial_url("ascii:///dev/ttyS0?parity=none");
    ASSERT_TRUE(ascii);
    EXPECT_EQ(transport::format_serial_url(*ascii),
              "ascii:///dev/ttyS0?baud=19200&parity=N&stop=1&data=7");
}

TEST(SerialUrl, ReadsRtuOverTcp) {
    auto url = transport::parse_serial_url("rtu+tcp://127.0.0.1:1502");
    ASSERT_TRUE(url) << url.error();
    EXPECT_EQ(url->kind, SerialUrl::Kind::RtuOverTcp);
    EXPECT_EQ(url->endpoint.port(), 1502);
    EXPECT_EQ(transport::format_serial_url(*url), "rtu+tcp://127.0.0.1:1502");
    EXPECT_TRUE(transport::is_serial_url("rtu+tcp://127.0.0.1:1502"));
    EXPECT_TRUE(transport::is_serial_url("ascii:///dev/ttyS0"));
    EXPECT_FALSE(transport::is_serial_url("tcp://127.0.0.1:502"));
}

TEST(SerialUrl, NamesWhatIsWrongInOneLine) {
    const std::string expected =
        " (expected rtu:///dev/ttyUSB0?baud=19200&parity=E&stop=1&data=8, ascii:///dev/... or "
        "rtu+tcp://HOST:PORT)";
    EXPECT_EQ(error_of("rtu:///dev/ttyS0?baud=12345"),
              "bad address 'rtu:///dev/ttyS0?baud=12345': baud must be a standard rate such as "
              "9600, 19200, 38400 or 115200" +
                  expected);
    EXPECT_EQ(error_of("rtu:///dev/ttyS0?parity=X"),
              "bad address 'rtu:///dev/ttyS0?parity=X': parity must be N, E or O" + expected);
    EXPECT_EQ(error_of("rtu:///dev/ttyS0?stop=3"),
              "bad address 'rtu:///dev/ttyS0?stop=3': stop must be 1 or 2 (stop bits)" + expected);
    EXPECT_EQ(error_of("rtu:///dev/ttyS0?data=7"),
              "bad address 'rtu:///dev/ttyS0?data=7': RTU needs 8 data bits" + expected);
    EXPECT_EQ(error_of("ascii:///dev/ttyS0?data=9"),
              "bad address 'ascii:///dev/ttyS0?data=9': data must be 7 or 8 (bits per character)" +
                  expected);
    EXPECT_EQ(error_of("rtu:///dev/ttyS0?speed=9600"),
              "bad address 'rtu:///dev/ttyS0?speed=9600': unknown setting (known: baud, parity, "
              "stop, data, strict, pace, timeout, units)" +
                  expected);
    EXPECT_EQ(error_of("rtu:///dev/ttyS0?pace=yes"),
              "bad address 'rtu:///dev/ttyS0?pace=yes': pace must be 0 or 1" + expected);
    EXPECT_EQ(error_of("rtu:///dev/ttyS0?baud"),
              "bad address 'rtu:///dev/ttyS0?baud': settings are KEY=VALUE" + expected);
    EXPECT_EQ(error_of("rtu://ttyS0"),
              "bad address 'rtu://ttyS0': the device must be an absolute path such as "
              "/dev/ttyUSB0" +
                  expected);
    EXPECT_EQ(error_of("rtu:///dev/ttyS0?units=0-300"),
              "bad address 'rtu:///dev/ttyS0?units=0-300': units must list unit ids 0..255 like "
              "1-10,20" +
                  expected);
    EXPECT_EQ(error_of("rtu:///dev/ttyS0?timeout=0"),
              "bad address 'rtu:///dev/ttyS0?timeout=0': timeout must be milliseconds from 1 to "
              "600000" +
                  expected);
    EXPECT_EQ(error_of("rtu+tcp://plc 01:502"),
              "bad address 'rtu+tcp://plc 01:502': HOST:PORT must be a host name or IP address "
              "and a port" +
                  expected);
    EXPECT_EQ(error_of("modbus:///dev/ttyS0"),
              "bad address 'modbus:///dev/ttyS0': unknown scheme" + expected);
}

TEST(SerialTiming, FollowsTheBaudRateUpTo19200AndIsFixedAbove) {
    // 11 bits a character: t3.5 = 38.5 bit times, t1.5 = 16.5, rounded up to microseconds.
    EXPECT_EQ(transport::rtu_char_times(9600).t35.count(), 4011);
    EXPECT_EQ(transport::rtu_char_times(9600).t15.count(), 1719);
    EXPECT_EQ(transport::rtu_char_times(19200).t35.count(), 2006);
    EXPECT_EQ(transport::rtu_char_times(19200).t15.count(), 860);
    EXPECT_EQ(transport::rtu_char_times(38400).t35.count(), 1750);
    EXPECT_EQ(transport::rtu_char_times(115200).t15.count(), 750);
}

TEST(SerialUrl, PaceKeepsALinesTimingAndIsSpelledOut) {
    auto url = transport::parse_serial_url("ascii:///dev/ttyS0?pace=1&baud=9600");
    ASSERT_TRUE(url) << url.error();
    EXPECT_TRUE(url->paced);
    EXPECT_EQ(transport::format_serial_url(*url),
              "ascii:///dev/ttyS0?baud=9600&parity=E&stop=1&data=7&pace=1");
    EXPECT_FALSE(transport::parse_serial_url("rtu:///dev/ttyS0")->paced);
}

TEST(SerialTiming, ACharacterIsStartDataParityAndStopBits) {
    transport::SerialSettings line;  // 19200 8E1: 11 bits
    EXPECT_EQ(transport::character_time(line).count(), 572916);
    line.parity = Parity::None;  // 8N1: 10 bits
    EXPECT_EQ(transport::character_time(line).count(), 520833);
    line.baud = 9600;
    line.data_bits = 7;
    line.parity = Parity::Even;  // 7E1 (ASCII's default): 10 bits
    EXPECT_EQ(transport::character_time(line).count(), 1041666);
}

TEST(SerialPort, NamesTheDeviceAndTheFixWhenItCannotOpen) {
    asio::io_context io;
    transport::SerialSettings settings;
    settings.device = "/dev/mblab-no-such-port";
    auto port = transport::open_serial_port(io.get_executor(), settings);
    ASSERT_FALSE(port);
    EXPECT_EQ(port.error(),
              "cannot open serial port /dev/mblab-no-such-port: No such file or directory (check "
              "the device path, e.g. ls /dev/ttyUSB* /dev/ttyACM*)");
}

// An unplugged adapter (here: the pty pair going away) ends the server with one message.
TEST(SerialPort, ReportsALineThatHangsUp) {
    auto pty = std::make_unique<PtyPair>();
    ASSERT_TRUE(pty->ok()) << pty->error();
    auto url = transport::parse_serial_url("rtu://" + pty->server_end());
    ASSERT_TRUE(url);
    auto loaded = device::load_profile(device::profiles_dir() / "reference.toml");
    ASSERT_TRUE(loaded) << loaded.error();
    asio::io_context io;
    auto server = server::start_serial_server(io, *loaded.value(), *url);
    ASSERT_TRUE(server) << server.error();
    std::vector<std::string> failures;
    (*server)->on_failure([&](const std::string& why) { failures.push_back(why); });
    auto ran = std::async(std::launch::async, [&] { io.run(); });
    pty.reset();  // kills socat
    // With the line gone the session ends, and with it the io_context's work.
    const auto status = ran.wait_for(10s);
    if (status != std::future_status::ready) io.stop();  // fail, but do not hang
    ASSERT_EQ(status, std::future_status::ready);
    EXPECT_EQ(failures, std::vector<std::string>{"serial line " + url->line.device +
                                                 " failed: the line hung up"});
}

}  // namespace
}  // namespace mblab::test
