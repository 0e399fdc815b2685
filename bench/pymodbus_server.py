"""pymodbus 3.0's asyncio TCP server for the benchmark: 10000 holding registers on unit 1.
Usage: pymodbus_server.py PORT"""
import asyncio
import logging
import sys

from pymodbus.datastore import (ModbusSequentialDataBlock, ModbusServerContext,
                                ModbusSlaveContext)
from pymodbus.server import StartAsyncTcpServer

logging.disable(logging.CRITICAL)
block = ModbusSequentialDataBlock(0, [0] * 10000)
store = ModbusSlaveContext(hr=block, ir=block, co=block, di=block)
context = ModbusServerContext(slaves={1: store}, single=False)
asyncio.run(StartAsyncTcpServer(context, address=("127.0.0.1", int(sys.argv[1]))))
