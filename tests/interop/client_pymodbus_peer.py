"""pymodbus 3.0 as the other end of mblab's client interop tests.

  client_pymodbus_peer.py PORT write-holding ADDR VALUE...   FC 16
  client_pymodbus_peer.py PORT read-holding ADDR COUNT       FC 03, prints the values
  client_pymodbus_peer.py PORT write-coils ADDR 0|1...       FC 15
  client_pymodbus_peer.py PORT read-coils ADDR COUNT         FC 01, prints 0/1
  client_pymodbus_peer.py PORT write-float ADDR VALUE        FC 16, f32 high word first

Talks to 127.0.0.1:PORT, unit 1; prints the values read one a line, exits 1 on any error.
Run with /usr/bin/python3 (Debian's python3-pymodbus).
"""
import logging
import struct
import sys

from pymodbus.client import ModbusTcpClient


def main(argv):
    port, action, address = int(argv[1]), argv[2], int(argv[3], 0)
    values = argv[4:]
    logging.basicConfig(level=logging.CRITICAL)
    client = ModbusTcpClient("127.0.0.1", port=port, timeout=3)
    if not client.connect():
        print("cannot connect", file=sys.stderr)
        return 1
    try:
        if action == "write-holding":
            answer = client.write_registers(address, [int(v, 0) for v in values], slave=1)
        elif action == "write-float":
            high, low = struct.unpack(">HH", struct.pack(">f", float(values[0])))
            answer = client.write_registers(address, [high, low], slave=1)
        elif action == "write-coils":
            answer = client.write_coils(address, [v == "1" for v in values], slave=1)
        elif action == "read-holding":
            answer = client.read_holding_registers(address, int(values[0]), slave=1)
            if not answer.isError():
                print("\n".join(str(r) for r in answer.registers))
        elif action == "read-coils":
            count = int(values[0])
            answer = client.read_coils(address, count, slave=1)
            if not answer.isError():
                print("\n".join("1" if b else "0" for b in answer.bits[:count]))
        else:
            print("unknown action " + action, file=sys.stderr)
            return 1
        if answer.isError():
            print("error: " + str(answer), file=sys.stderr)
            return 1
        return 0
    finally:
        client.close()


if __name__ == "__main__":
    sys.exit(main(sys.argv))
