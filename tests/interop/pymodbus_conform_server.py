"""A pymodbus 3.0 asyncio Modbus/TCP server for mblab's conformance interop test.

Listens on 127.0.0.1 on an ephemeral port, prints the port on the first line of stdout, and
serves 65536 coils, discrete inputs, holding and input registers (zero-based addresses) for
every unit id, with the basic device identification objects. Stops by itself after --lifetime seconds so a failed test cannot leave it behind.
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
from pymodbus.server.async_io import ModbusTcpServer

ADDRESSES = 65536


def block():
    return ModbusSequentialDataBlock(0, [0] * ADDRESSES)


async def serve(lifetime, framer):
    store = ModbusSlaveContext(di=block(), co=block(), hr=block(), ir=block(), zero_mode=True)
    context = ModbusServerContext(slaves=store, single=True)
    # The basic identification objects (vendor, product code, revision) are mandatory.
    identity = ModbusDeviceIdentification(
        info_name={
            "VendorName": "pymodbus",
            "ProductCode": "PM",
            "MajorMinorRevision": "3.0.0",
        }
    )
    # --framer rtu: RTU frames (address, PDU, CRC) over the TCP connection instead of MBAP.
    framers = {"socket": ModbusSocketFramer, "rtu": ModbusRtuFramer}
    server = ModbusTcpServer(
        context,
        framer=framers[framer],
        identity=identity,
        address=("127.0.0.1", 0),
        allow_reuse_address=True,
    )
    task = asyncio.create_task(server.serve_forever())
    await server.serving
    print(server.server.sockets[0].getsockname()[1], flush=True)
    try:
        await asyncio.wait_for(task, timeout=lifetime)
    except asyncio.TimeoutError:
        pass


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--lifetime", type=float, default=120.0)
    parser.add_argument("--framer", choices=["socket", "rtu"], default="socket")
    args = parser.parse_args()
    logging.basicConfig(level=logging.CRITICAL)
    asyncio.run(serve(args.lifetime, args.framer))
    return 0


if __name__ == "__main__":
    sys.exit(main())
