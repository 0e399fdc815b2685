"""pymodbus 3.0's TLS client against `mblab serve --listen mbaps://`.

Usage: pymodbus_tls_client.py PORT PKI_DIR MODE
  mbap      MBAP inside TLS (pymodbus's socket framer), as [SEC] says: an Operator reads and
            writes, a ReadOnly client's write is answered exception 01, a role-less client's read
            is answered exception 01.
  bare-pdu  pymodbus's default TLS framer (the bare PDU of an early draft): no answer may come.
Exits 0 when every check holds, 1 with the failing check on stderr.
"""
import asyncio
import ssl
import sys

from pymodbus.client import AsyncModbusTlsClient
from pymodbus.framer.socket_framer import ModbusSocketFramer
from pymodbus.framer.tls_framer import ModbusTlsFramer

PORT = int(sys.argv[1])
PKI = sys.argv[2]
MODE = sys.argv[3]


def context(name):
    ctx = ssl.SSLContext(ssl.PROTOCOL_TLS_CLIENT)
    ctx.minimum_version = ssl.TLSVersion.TLSv1_2
    ctx.load_verify_locations(f"{PKI}/ca.pem")
    ctx.load_cert_chain(f"{PKI}/{name}.pem", f"{PKI}/{name}.key")
    return ctx


# pymodbus 3.0's sync TLS client waits with select() on the socket between reading an answer's
# header and its rest, which never wakes when the rest is already decrypted inside the TLS layer
# (it came in the same record): it cannot read any answer from any TLS server. Its asyncio
# client reads through the TLS transport and works.
async def client(name, framer=ModbusSocketFramer):
    c = AsyncModbusTlsClient("127.0.0.1", port=PORT, framer=framer, sslctx=context(name),
                             server_hostname="localhost", timeout=2, retries=0)
    await c.connect()
    if not c.connected:
        sys.exit(f"{name}: cannot connect")
    return c


def check(condition, what):
    if not condition:
        sys.exit(f"FAIL: {what}")
    print(f"ok: {what}")


async def main():
    if MODE == "mbap":
        operator = await client("client-Operator")
        rr = await operator.read_holding_registers(0, 2, slave=1)
        check(not rr.isError() and rr.registers == [0x5345, 0x4D49],
              f"Operator reads holding 0..1 as 5345 4D49 (got {rr})")
        wr = await operator.write_register(20, 0x1234, slave=1)
        check(not wr.isError(), f"Operator writes holding 20 (got {wr})")
        rr = await operator.read_holding_registers(20, 1, slave=1)
        check(not rr.isError() and rr.registers == [0x1234], f"holding 20 reads back 1234 ({rr})")
        operator.close()

        reader = await client("client-ReadOnly")
        wr = await reader.write_register(20, 0x9999, slave=1)
        check(wr.isError() and wr.exception_code == 1,
              f"ReadOnly's write is answered exception 01 (got {wr})")
        rr = await reader.read_holding_registers(20, 1, slave=1)
        check(not rr.isError() and rr.registers == [0x1234],
              f"the refused write changed nothing (got {rr})")
        reader.close()

        nobody = await client("client-norole")
        rr = await nobody.read_holding_registers(0, 1, slave=1)
        check(rr.isError() and rr.exception_code == 1,
              f"a certificate without a role is answered exception 01 (got {rr})")
        nobody.close()
    elif MODE == "bare-pdu":
        bare = await client("client-Operator", framer=ModbusTlsFramer)
        try:
            rr = await bare.read_holding_registers(0, 2, slave=1)
        except Exception as error:  # pylint: disable=broad-except
            rr = error  # the server closed the session: no answer, as expected
        check(not hasattr(rr, "registers"),
              f"a bare-PDU request gets no Modbus answer (got {rr})")
        bare.close()
    else:
        sys.exit(f"unknown mode {MODE}")


asyncio.run(main())
