"""pymodbus (Debian's 3.0) as a serial master: writes registers and coils to unit 1, then reads
them back and prints what it read, one line each.

Usage: pymodbus_serial_master.py rtu|ascii PORT BAUD
       pymodbus_serial_master.py rtu+tcp HOST PORT
Exits non-zero with the reason when a request fails.
"""
import sys

from pymodbus.client import ModbusSerialClient, ModbusTcpClient
from pymodbus.framer.ascii_framer import ModbusAsciiFramer
from pymodbus.framer.rtu_framer import ModbusRtuFramer


def connect(kind, where, number):
    if kind == "rtu+tcp":
        return ModbusTcpClient(where, port=int(number), framer=ModbusRtuFramer, timeout=3)
    framer = ModbusRtuFramer if kind == "rtu" else ModbusAsciiFramer
    # strict=False: pymodbus's strict RTU timing sets an inter-byte timeout a pty refuses.
    return ModbusSerialClient(where, framer=framer, baudrate=int(number), bytesize=8,
                              parity="E", stopbits=1, timeout=3, strict=False)


def check(result):
    if result.isError():
        sys.exit("error: " + str(result))
    return result


def main():
    kind, where, number = sys.argv[1:4]
    client = connect(kind, where, number)
    if not client.connect():
        sys.exit("cannot open " + where)
    check(client.write_registers(100, [0x1234, 0xFFFF, 0x00FF, 7], slave=1))
    check(client.write_register(104, 0xFF00, slave=1))
    print("registers", check(client.read_holding_registers(100, 5, slave=1)).registers)
    check(client.write_coils(20, [True, False, True, True, False, False, True, True, True],
                             slave=1))
    check(client.write_coil(29, True, slave=1))
    print("coils", check(client.read_coils(20, 10, slave=1)).bits[:10])
    client.close()


if __name__ == "__main__":
    main()
