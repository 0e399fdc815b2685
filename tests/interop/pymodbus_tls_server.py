"""pymodbus 3.0's TLS server with MBAP framing and client certificates required, for `mblab read
mbaps://`. Holding registers 0..9 hold 100..109. Usage: pymodbus_tls_server.py PORT PKI_DIR"""
import ssl
import sys

from pymodbus.datastore import (ModbusSequentialDataBlock, ModbusServerContext,
                                ModbusSlaveContext)
from pymodbus.framer.socket_framer import ModbusSocketFramer
from pymodbus.server import StartTlsServer

PORT = int(sys.argv[1])
PKI = sys.argv[2]

ctx = ssl.SSLContext(ssl.PROTOCOL_TLS_SERVER)
ctx.minimum_version = ssl.TLSVersion.TLSv1_2
ctx.verify_mode = ssl.CERT_REQUIRED
ctx.load_verify_locations(f"{PKI}/ca.pem")
ctx.load_cert_chain(f"{PKI}/server.pem", f"{PKI}/server.key")

block = ModbusSequentialDataBlock(0, [100 + i for i in range(10)])
store = ModbusSlaveContext(hr=block, zero_mode=True)
StartTlsServer(context=ModbusServerContext(slaves=store, single=True), framer=ModbusSocketFramer,
               sslctx=ctx, address=("127.0.0.1", PORT))
