// Interop: pymodbus's serial client (Debian's python3-pymodbus 3.0) as the master of our serial
// server, RTU and ASCII, at 9600 and 115200 baud, over a socat pty pair: it writes registers
// and coils, then reads them back.
#include <gtest/gtest.h>

#include <string>
#include <tuple>

#include "serial_test_support.hpp"

namespace mblab::test {
namespace {

// The master script the interop scripts use too: rtu|ascii PORT BAUD.
const std::string kMasterScript =
    std::string(MBLAB_SOURCE_DIR) + "/tests/interop/pymodbus_serial_master.py";

class PymodbusMaster : public ::testing::TestWithParam<std::tuple<const char*, unsigned>> {};

TEST_P(PymodbusMaster, WritesThenReadsBack) {
    const auto [scheme, baud] = GetParam();
    DeviceOnLine line;
    ASSERT_EQ(line.start("reference", scheme, baud, false), "");
    std::string output;
    const int status = run_command(
        {"/usr/bin/python3", kMasterScript, scheme, line.pty().client_end(), std::to_string(baud)},
        output, 60s);
    EXPECT_EQ(status, 0) << output;
    EXPECT_EQ(output,
              "registers [4660, 65535, 255, 7, 65280]\n"
              "coils [True, False, True, True, False, False, True, True, True, True]\n");
    // What pymodbus wrote is in the device.
    EXPECT_EQ(line.device().data().value(1, device::BankKind::HoldingRegisters, 101), 0xFFFF);
}

INSTANTIATE_TEST_SUITE_P(Lines, PymodbusMaster,
                         ::testing::Combine(::testing::Values("rtu", "ascii"),
                                            ::testing::Values(9600u, 115200u)),
                         [](const auto& info) {
                             return std::string(std::get<0>(info.param)) + "_" +
                                    std::to_string(std::get<1>(info.param));
                         });

}  // namespace
}  // namespace mblab::test
