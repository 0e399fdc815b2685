// Interop: pymodbus's serial client (Debian's python3-pymodbus 3.0) as the master of our serial
// server, RTU and ASCII, at 9600 and 115200 baud, over a socat pty pair: it writes registers
// and coils, then reads them back.
#include <gtest/gtest.h>

#include <string>
#include <tuple>

#include "serial_test_support.hpp"

namespace mblab::test {
namespace {

// argv: port, framer ("rtu" or "ascii"), baud. Prints what it read back, one line each.
constexpr const char* kMasterScript = R"(
import sys
from pymodbus.client import ModbusSerialClient
from pymodbus.framer.ascii_framer import ModbusAsciiFramer
from pymodbus.framer.rtu_framer import ModbusRtuFramer

port, framer, baud = sys.argv[1], sys.argv[2], int(sys.argv[3])
# strict=False: pymodbus's strict RTU timing sets an inter-byte timeout that a pty refuses.
client = ModbusSerialClient(port, framer=ModbusRtuFramer if framer == "rtu" else ModbusAsciiFramer,
                            baudrate=baud, bytesize=8, parity="E", stopbits=1, timeout=3,
                            strict=False)
if not client.connect():
    sys.exit("cannot open " + port)

def check(result):
    if result.isError():
        sys.exit("error: " + str(result))
    return result

check(client.write_registers(100, [0x1234, 0xFFFF, 0x00FF, 7], slave=1))
check(client.write_register(104, 0xFF00, slave=1))
print("registers", check(client.read_holding_registers(100, 5, slave=1)).registers)
check(client.write_coils(20, [True, False, True, True, False, False, True, True, True], slave=1))
check(client.write_coil(29, True, slave=1))
print("coils", check(client.read_coils(20, 10, slave=1)).bits[:10])
client.close()
)";

class PymodbusMaster : public ::testing::TestWithParam<std::tuple<const char*, unsigned>> {};

TEST_P(PymodbusMaster, WritesThenReadsBack) {
    const auto [scheme, baud] = GetParam();
    DeviceOnLine line;
    ASSERT_EQ(line.start("reference", scheme, baud, false), "");
    std::string output;
    const int status = run_command({"/usr/bin/python3", "-c", kMasterScript,
                                    line.pty().client_end(), scheme, std::to_string(baud)},
                                   output, 60s);
    EXPECT_EQ(status, 0) << output;
    EXPECT_EQ(output,
              "registers [4660, 65535, 255, 7, 65280]\n"
              "coils [True, False, True, True, False, False, True, True, True, True]\n");
    // What pymodbus wrote is in the device.
    EXPECT_EQ(line.device().value(1, device::BankKind::HoldingRegisters, 101), 0xFFFF);
}

INSTANTIATE_TEST_SUITE_P(
    Lines, PymodbusMaster,
    ::testing::Combine(::testing::Values("rtu", "ascii"), ::testing::Values(9600u, 115200u)),
    [](const auto& info) {
        return std::string(std::get<0>(info.param)) + "_" + std::to_string(std::get<1>(info.param));
    });

}  // namespace
}  // namespace mblab::test
