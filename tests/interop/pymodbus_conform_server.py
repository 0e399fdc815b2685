"""A pymodbus 3.0 asyncio Modbus/TCP server for mblab's conformance interop test.

Listens on 127.0.0.1 on an ephemeral port, prints the port on the first line of stdout, and
serves 65536 coils, discrete inputs, holding and input registers (zero-based addresses) for
every unit id, with the basic device identification objects. With --serial PATH it is instead an
RTU slave on that serial port (a pty end) answering its one address, --unit, as a device on a
multi-drop line is set up: other addresses ignored, 0 taken as a broadcast; it prints "ready".
Stops by itself after --lifetime seconds so a failed test cannot leave it behind.
Run with /usr/bin/python3 (Debian's python3-pymodbus).
"""
import argparse
import asyncio
import logging
import sys

from pymodbus.datastore import (
    ModbusSequentialDataBlock,
    ModbusServerContext,
    ModbusSlaveContext,
)
from pymodbus.device import ModbusDeviceIdentification
from pymodbus.framer.rtu_framer import ModbusRtuFramer
from pymodbus.framer.socket_framer import ModbusSocketFramer
from pymodbus.server.async_io import ModbusSerialServer, ModbusTcpServer

ADDRESSES = 65536


def block():
    return ModbusSequentialDataBlock(0, [0] * ADDRESSES)


async def serve(args):
    store = ModbusSlaveContext(di=block(), co=block(), hr=block(), ir=block(), zero_mode=True)
    if args.serial:
        context = ModbusServerContext(slaves={args.unit: store}, single=False)
    else:
        context = ModbusServerContext(slaves=store, single=True)
    # The basic identification objects (vendor, product code, revision) are mandatory.
    identity = ModbusDeviceIdentification(
        info_name={
            "VendorName": "pymodbus",
            "ProductCode": "PM",
            "MajorMinorRevision": "3.0.0",
        }
    )
    if args.serial:
        server = ModbusSerialServer(
            context,
            framer=ModbusRtuFramer,
            identity=identity,
            port=args.serial,
            baudrate=args.baud,
            ignore_missing_slaves=True,
            broadcast_enable=True,
        )
        await server.start()
        print("ready", flush=True)
        await asyncio.sleep(args.lifetime)
        return
    # --framer rtu: RTU frames (address, PDU, CRC) over the TCP connection instead of MBAP.
    framers = {"socket": ModbusSocketFramer, "rtu": ModbusRtuFramer}
    server = ModbusTcpServer(
        context,
        framer=framers[args.framer],
        identity=identity,
        address=("127.0.0.1", 0),
        allow_reuse_address=True,
    )
    task = asyncio.create_task(server.serve_forever())
    await server.serving
    print(server.server.sockets[0].getsockname()[1], flush=True)
    try:
        await asyncio.wait_for(task, timeout=args.lifetime)
    except asyncio.TimeoutError:
        pass


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--lifetime", type=float, default=120.0)
    parser.add_argument("--framer", choices=["socket", "rtu"], default="socket")
    parser.add_argument("--serial", help="serve RTU on this serial port instead of TCP")
    parser.add_argument("--baud", type=int, default=19200)
    parser.add_argument("--unit", type=int, default=1)
    args = parser.parse_args()
    logging.basicConfig(level=logging.CRITICAL)
    asyncio.run(serve(args))
    return 0


if __name__ == "__main__":
    sys.exit(main())
