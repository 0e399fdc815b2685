"""pymodbus 3.0's synchronous TCP or RTU client as an application would use it, examined by
`mblab conform-client`: reads COUNT holding registers at ADDRESS of UNIT, prints their values,
and ends with status 1 on any error pymodbus reports (an exception response or no answer).
Usage: pymodbus_read_client.py HOST PORT UNIT ADDRESS COUNT TIMEOUT RETRIES
       pymodbus_read_client.py /dev/DEVICE BAUD UNIT ADDRESS COUNT TIMEOUT RETRIES   (RTU, 8E1)"""
import sys

from pymodbus.client import ModbusSerialClient, ModbusTcpClient

host, port, unit, address, count = sys.argv[1], int(sys.argv[2]), *map(int, sys.argv[3:6])
timing = {"timeout": float(sys.argv[6]), "retries": int(sys.argv[7])}
if host.startswith("/dev/"):
    # strict=False: pymodbus's strict RTU timing sets an inter-byte timeout a pty refuses.
    client = ModbusSerialClient(host, method="rtu", baudrate=port, bytesize=8, parity="E",
                                stopbits=1, strict=False, **timing)
else:
    client = ModbusTcpClient(host, port=port, **timing)
try:
    if not client.connect():
        print(f"error: cannot connect to {host}")
        sys.exit(1)
    response = client.read_holding_registers(address, count, slave=unit)
except Exception as error:  # pymodbus raises ModbusIOException and others on a lost answer
    print(f"error: {error}")
    sys.exit(1)
finally:
    client.close()
if response.isError():
    print(f"error: {response}")
    sys.exit(1)
print(" ".join(str(value) for value in response.registers))
